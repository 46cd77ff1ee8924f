//! The GDAL VRT parser: the XML of a virtual mosaic (`gdalbuildvrt`'s output and what people
//! write by hand in its common subset) into a [`VrtMosaic`], a description of which window of
//! which file goes where. It reads no source file and no height: the mosaic (`mosaic/`) lays
//! the sources out and reads them. The options and errors a user meets:
//! `docs/experiment-format.md`, "Mosaics".
//!
//! **The subset read.** A `VRTDataset` with `rasterXSize`/`rasterYSize`, an optional
//! `GeoTransform` (north-up: no rotation terms, a negative row step) and `SRS`, and exactly one
//! `VRTRasterBand` holding an optional `NoDataValue` and `SimpleSource`/`ComplexSource`
//! elements, each with a `SourceFilename` (`relativeToVRT="1"`: relative to the VRT's folder,
//! as GDAL resolves it), `SourceBand` 1, and `SrcRect`/`DstRect` windows of the same size
//! (GDAL's defaults when absent: the whole source, the whole raster). A `ComplexSource` may
//! carry `NODATA` and the identity `ScaleOffset` 0 / `ScaleRatio` 1. Descriptive elements
//! (`Metadata`, `ColorInterp`, `Description`, `SourceProperties`, block sizes, overviews) are
//! ignored: they change no height.
//!
//! **Everything else is refused by name**, never ignored: a window that would resample (its
//! source and destination sizes differ), another band, a derived or warped dataset, pixel
//! functions, kernel or averaged sources, lookup tables, scaling, masks, GCPs, open options and
//! GDAL's virtual file systems (`/vsicurl/…`); the mosaic refuses a nested `.vrt` source. A
//! window that leaves the raster is refused rather than clipped. `dataType` is not applied:
//! heights are the sources' values as their readers give them.
//!
//! **Why `roxmltree`.** The file is small and read once, so a read-only DOM is the simplest
//! correct reader; `roxmltree` is pure Rust, has no dependency beyond `memchr`, refuses DTDs by
//! default (no entity expansion from a hostile file) and reports the line and column of a
//! syntax error. A streaming parser (`quick-xml`) would save nothing here and make the
//! "unknown element" checks longer.

use super::TerrainReadError;
use super::mosaic::Window;
use std::path::{Path, PathBuf};

/// A VRT's mosaic as its XML declares it; nothing in it has been opened yet.
#[derive(Clone, Debug, PartialEq)]
pub struct VrtMosaic {
    pub(super) columns: usize,
    pub(super) rows: usize,
    /// GDAL's six affine coefficients (top-left corner of the top-left pixel), north-up.
    pub(super) geo_transform: Option<[f64; 6]>,
    /// The `SRS` text (WKT or `EPSG:…`), if any.
    pub(super) srs: Option<String>,
    /// The band's `NoDataValue`.
    pub(super) nodata: Option<f64>,
    pub(super) sources: Vec<VrtSource>,
}

/// One `SimpleSource` or `ComplexSource`: a window of a file placed in the raster.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct VrtSource {
    /// Resolved against the VRT's folder when `relativeToVRT="1"`.
    pub(super) path: PathBuf,
    /// `SrcRect`, in the file's own pixels from its north-west corner; `None`: the whole file.
    pub(super) source_window: Option<Window>,
    /// `DstRect`, in the raster's pixels from its north-west corner; `None`: the whole raster.
    pub(super) destination_window: Option<Window>,
    /// A `ComplexSource`'s `NODATA`.
    pub(super) nodata: Option<f64>,
}

impl VrtMosaic {
    /// The raster's size in columns and rows.
    pub fn size(&self) -> (usize, usize) {
        (self.columns, self.rows)
    }

    pub fn n_sources(&self) -> usize {
        self.sources.len()
    }
}

/// The largest raster side accepted: GDAL's own limit (`INT_MAX`), far above any terrain this
/// simulator can hold, and low enough that no product of two sides overflows.
const MAX_SIDE: usize = i32::MAX as usize;

/// The most XML nodes read: a VRT of 100 000 sources has about 2 million; a hostile file with
/// more is refused before it fills memory.
const MAX_XML_NODES: u32 = 4_000_000;

/// Parses a VRT's bytes; `path` names the file in errors and is the folder `relativeToVRT`
/// source names are resolved against. No IO.
pub fn parse_vrt_bytes(path: &Path, bytes: &[u8]) -> Result<VrtMosaic, TerrainReadError> {
    let error = |problem: String| TerrainReadError::new(path, problem);
    let text = std::str::from_utf8(bytes).map_err(|utf8| {
        error(format!(
            "the VRT is not UTF-8 text ({utf8}); expected a GDAL VRT (XML)"
        ))
    })?;
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_XML_NODES,
        ..roxmltree::ParsingOptions::default()
    };
    let document = roxmltree::Document::parse_with_options(text, options)
        .map_err(|xml| error(format!("the VRT is not well-formed XML: {xml}")))?;
    let dataset = document.root_element();
    if dataset.tag_name().name() != "VRTDataset" {
        return Err(error(format!(
            "the root element is <{}>; expected <VRTDataset>",
            dataset.tag_name().name()
        )));
    }
    if let Some(sub_class) = dataset.attribute("subClass") {
        return Err(error(format!(
            "<VRTDataset subClass=\"{sub_class}\"> is not read; expected a plain mosaic \
             (no warped or pansharpened dataset)"
        )));
    }
    let columns = size_attribute(path, dataset, "VRTDataset", "rasterXSize")?;
    let rows = size_attribute(path, dataset, "VRTDataset", "rasterYSize")?;

    let mut geo_transform = None;
    let mut srs = None;
    let mut band = None;
    for child in dataset.children().filter(roxmltree::Node::is_element) {
        match child.tag_name().name() {
            "GeoTransform" => geo_transform = Some(parse_geo_transform(path, child)?),
            "SRS" => srs = Some(child.text().unwrap_or("").trim().to_string()),
            "VRTRasterBand" => {
                if band.is_some() {
                    return Err(error(
                        "the VRT has more than one <VRTRasterBand>; expected a single band of \
                         heights"
                            .to_string(),
                    ));
                }
                band = Some(child);
            }
            "Metadata" | "BlockXSize" | "BlockYSize" | "OverviewList" => {}
            other => {
                return Err(error(format!(
                    "<VRTDataset> holds <{other}>, which is not read; expected only \
                     <GeoTransform>, <SRS>, <Metadata> and one <VRTRasterBand>"
                )));
            }
        }
    }
    let band =
        band.ok_or_else(|| error("the VRT has no <VRTRasterBand>; expected one".to_string()))?;
    let (nodata, sources) = parse_band(path, band)?;
    for (k, source) in sources.iter().enumerate() {
        if let Some(window) = source.destination_window
            && (window.column + window.columns > columns || window.row + window.rows > rows)
        {
            return Err(error(format!(
                "source {} ({}): its <DstRect> {} reaches past the {columns}×{rows} raster; \
                 expected a window inside it",
                k + 1,
                source.path.display(),
                window.describe()
            )));
        }
    }
    Ok(VrtMosaic {
        columns,
        rows,
        geo_transform,
        srs,
        nodata,
        sources,
    })
}

/// The band's nodata value and its sources.
fn parse_band(
    path: &Path,
    band: roxmltree::Node,
) -> Result<(Option<f64>, Vec<VrtSource>), TerrainReadError> {
    let error = |problem: String| TerrainReadError::new(path, problem);
    if let Some(sub_class) = band.attribute("subClass") {
        return Err(error(format!(
            "<VRTRasterBand subClass=\"{sub_class}\"> is not read; expected a plain band of \
             sources (no derived or raw band)"
        )));
    }
    if let Some(number) = band.attribute("band")
        && number.trim() != "1"
    {
        return Err(error(format!(
            "<VRTRasterBand band=\"{number}\">: expected band 1, the only one read"
        )));
    }
    let mut nodata = None;
    let mut sources = Vec::new();
    for child in band.children().filter(roxmltree::Node::is_element) {
        match child.tag_name().name() {
            "NoDataValue" => nodata = Some(number_text(path, child, "NoDataValue")?),
            name @ ("Offset" | "Scale") => {
                let value = number_text(path, child, name)?;
                let identity = if name == "Offset" { 0.0 } else { 1.0 };
                if value != identity {
                    return Err(error(format!(
                        "<{name}> is {value}; expected {identity} (give the experiment's \
                         height_scale and height_offset_m instead)"
                    )));
                }
            }
            "UnitType" => {
                let unit = child.text().unwrap_or("").trim();
                if !matches!(unit, "" | "m" | "metre" | "meter" | "metres" | "meters") {
                    return Err(error(format!(
                        "<UnitType> is '{unit}'; expected metres (give the experiment's \
                         height_scale to convert other units)"
                    )));
                }
            }
            "ColorInterp" | "Description" | "Metadata" | "Overview" | "Histograms" => {}
            "SimpleSource" | "ComplexSource" => {
                sources.push(parse_source(path, child, sources.len() + 1)?);
            }
            other => {
                return Err(error(format!(
                    "<VRTRasterBand> holds <{other}>, which is not read; expected \
                     <SimpleSource> or <ComplexSource> elements and an optional <NoDataValue>"
                )));
            }
        }
    }
    if sources.is_empty() {
        return Err(error(
            "the band has no <SimpleSource> or <ComplexSource>; expected at least one".to_string(),
        ));
    }
    Ok((nodata, sources))
}

/// One source, the `number`-th of the band (from 1, for errors).
fn parse_source(
    path: &Path,
    source: roxmltree::Node,
    number: usize,
) -> Result<VrtSource, TerrainReadError> {
    let kind = source.tag_name().name();
    let error =
        |problem: String| TerrainReadError::new(path, format!("source {number}: {problem}"));
    let mut file = None;
    let mut source_window = None;
    let mut destination_window = None;
    let mut nodata = None;
    for child in source.children().filter(roxmltree::Node::is_element) {
        match child.tag_name().name() {
            "SourceFilename" => {
                let name = child.text().unwrap_or("").trim();
                if name.is_empty() {
                    return Err(error(
                        "<SourceFilename> is empty; expected a file name".to_string(),
                    ));
                }
                if name.starts_with("/vsi") {
                    return Err(error(format!(
                        "<SourceFilename> is '{name}', a GDAL virtual file system; expected a \
                         file on disk"
                    )));
                }
                let relative = match child.attribute("relativeToVRT").map(str::trim) {
                    None | Some("0") => false,
                    Some("1") => true,
                    Some(other) => {
                        return Err(error(format!(
                            "<SourceFilename relativeToVRT=\"{other}\">: expected 0 or 1"
                        )));
                    }
                };
                file = Some(if relative {
                    path.parent().unwrap_or(Path::new("")).join(name)
                } else {
                    PathBuf::from(name)
                });
            }
            "SourceBand" => {
                let band = child.text().unwrap_or("").trim();
                if band != "1" {
                    return Err(error(format!(
                        "<SourceBand> is '{band}'; expected 1 (the only band read)"
                    )));
                }
            }
            "SrcRect" => source_window = Some(parse_window(path, child, number)?),
            "DstRect" => destination_window = Some(parse_window(path, child, number)?),
            "NODATA" if kind == "ComplexSource" => {
                nodata = Some(number_text(path, child, "NODATA")?);
            }
            name @ ("ScaleOffset" | "ScaleRatio") if kind == "ComplexSource" => {
                let value = number_text(path, child, name)?;
                let identity = if name == "ScaleOffset" { 0.0 } else { 1.0 };
                if value != identity {
                    return Err(error(format!(
                        "<{name}> is {value}; expected {identity} (scaled sources are not read; \
                         give the experiment's height_scale and height_offset_m instead)"
                    )));
                }
            }
            "SourceProperties" => {}
            "OpenOptions" => {
                return Err(error(
                    "<OpenOptions> is not read; expected a source opened as it is".to_string(),
                ));
            }
            other => {
                return Err(error(format!(
                    "<{kind}> holds <{other}>, which is not read; expected <SourceFilename>, \
                     <SourceBand>, <SrcRect>, <DstRect>{}",
                    if kind == "ComplexSource" {
                        " and <NODATA>"
                    } else {
                        ""
                    }
                )));
            }
        }
    }
    let path = file.ok_or_else(|| error("no <SourceFilename>; expected one".to_string()))?;
    if let (Some(from), Some(to)) = (source_window, destination_window)
        && (from.columns != to.columns || from.rows != to.rows)
    {
        return Err(error(format!(
            "{}: <SrcRect> {} and <DstRect> {} differ in size, which would resample; expected \
             windows of the same size (resampling is not read)",
            path.display(),
            from.describe(),
            to.describe()
        )));
    }
    Ok(VrtSource {
        path,
        source_window,
        destination_window,
        nodata,
    })
}

/// A `SrcRect` or `DstRect`: whole, non-negative offsets and positive sizes (GDAL writes them as
/// decimals; a fraction would resample and is refused).
fn parse_window(
    path: &Path,
    rect: roxmltree::Node,
    number: usize,
) -> Result<Window, TerrainReadError> {
    let element = rect.tag_name().name();
    let mut values = [0_usize; 4];
    for (value, (name, minimum)) in
        values
            .iter_mut()
            .zip([("xOff", 0_usize), ("yOff", 0), ("xSize", 1), ("ySize", 1)])
    {
        let text = rect.attribute(name).ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!("source {number}: <{element}> has no {name}; expected xOff, yOff, xSize and ySize"),
            )
        })?;
        *value = whole_number(text)
            .filter(|&v| v >= minimum && v <= MAX_SIDE)
            .ok_or_else(|| {
                TerrainReadError::new(
                    path,
                    format!(
                        "source {number}: <{element}> {name} is '{text}'; expected a whole \
                         number from {minimum} to {MAX_SIDE}"
                    ),
                )
            })?;
    }
    let [column, row, columns, rows] = values;
    Ok(Window {
        column,
        row,
        columns,
        rows,
    })
}

fn size_attribute(
    path: &Path,
    node: roxmltree::Node,
    element: &str,
    name: &str,
) -> Result<usize, TerrainReadError> {
    let text = node.attribute(name).ok_or_else(|| {
        TerrainReadError::new(path, format!("<{element}> has no {name}; expected one"))
    })?;
    whole_number(text)
        .filter(|&v| (1..=MAX_SIDE).contains(&v))
        .ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!(
                    "<{element}> {name} is '{text}'; expected a whole number from 1 to {MAX_SIDE}"
                ),
            )
        })
}

/// A whole number written as an integer or as a decimal with no fraction ("1200", "1200.0").
fn whole_number(text: &str) -> Option<usize> {
    let text = text.trim();
    if let Ok(value) = text.parse::<usize>() {
        return Some(value);
    }
    let value = text.parse::<f64>().ok()?;
    (value.is_finite() && value >= 0.0 && value.fract() == 0.0 && value <= MAX_SIDE as f64)
        .then_some(value as usize)
}

fn number_text(path: &Path, node: roxmltree::Node, name: &str) -> Result<f64, TerrainReadError> {
    let text = node.text().unwrap_or("").trim();
    text.parse::<f64>().map_err(|_| {
        TerrainReadError::new(
            path,
            format!("<{name}> is '{text}'; expected a number such as -32768 or nan"),
        )
    })
}

/// `<GeoTransform>`: six finite numbers, north-up (no rotation, columns eastward, rows
/// southward).
fn parse_geo_transform(path: &Path, node: roxmltree::Node) -> Result<[f64; 6], TerrainReadError> {
    let text = node.text().unwrap_or("");
    let numbers: Vec<Option<f64>> = text
        .split(',')
        .map(|part| part.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect();
    let transform: Option<Vec<f64>> = numbers.into_iter().collect();
    let Some([x0, dx, rx, y0, ry, dy]) = transform.and_then(|t| <[f64; 6]>::try_from(t).ok())
    else {
        return Err(TerrainReadError::new(
            path,
            format!(
                "<GeoTransform> is '{}'; expected six finite numbers separated by commas",
                text.trim()
            ),
        ));
    };
    if rx != 0.0 || ry != 0.0 || dx <= 0.0 || dy >= 0.0 {
        return Err(TerrainReadError::new(
            path,
            format!(
                "<GeoTransform> is {x0}, {dx}, {rx}, {y0}, {ry}, {dy}: rotated, sheared or \
                 south-up rasters are not read; expected a north-up raster (second term \
                 positive, third and fifth 0, sixth negative)"
            ),
        ));
    }
    Ok([x0, dx, rx, y0, ry, dy])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<VrtMosaic, String> {
        parse_vrt_bytes(Path::new("data/tiles.vrt"), text.as_bytes()).map_err(|e| e.to_string())
    }

    fn vrt(band: &str) -> String {
        format!(
            "<VRTDataset rasterXSize=\"4\" rasterYSize=\"3\">\n\
             <GeoTransform> 9.0, 0.5, 0.0, 49.0, 0.0, -0.5</GeoTransform>\n\
             <VRTRasterBand dataType=\"Int16\" band=\"1\">{band}</VRTRasterBand>\n\
             </VRTDataset>"
        )
    }

    const TWO_SOURCES: &str = "<NoDataValue>-32768</NoDataValue>\
        <SimpleSource><SourceFilename relativeToVRT=\"1\">a.tif</SourceFilename>\
        <SourceBand>1</SourceBand><SrcRect xOff=\"0\" yOff=\"0\" xSize=\"2\" ySize=\"3\"/>\
        <DstRect xOff=\"0\" yOff=\"0\" xSize=\"2\" ySize=\"3\"/></SimpleSource>\
        <ComplexSource><SourceFilename relativeToVRT=\"0\">/abs/b.tif</SourceFilename>\
        <SourceBand>1</SourceBand><NODATA>0</NODATA>\
        <SrcRect xOff=\"1\" yOff=\"0\" xSize=\"2.0\" ySize=\"3\"/>\
        <DstRect xOff=\"2\" yOff=\"0\" xSize=\"2\" ySize=\"3\"/></ComplexSource>";

    #[test]
    fn sources_are_read_with_their_windows_and_resolved_paths() {
        let mosaic = parse(&vrt(TWO_SOURCES)).unwrap();
        assert_eq!(mosaic.size(), (4, 3));
        assert_eq!(mosaic.nodata, Some(-32768.0));
        assert_eq!(mosaic.geo_transform, Some([9.0, 0.5, 0.0, 49.0, 0.0, -0.5]));
        assert_eq!(mosaic.sources[0].path, Path::new("data/a.tif"));
        assert_eq!(mosaic.sources[1].path, Path::new("/abs/b.tif"));
        assert_eq!(mosaic.sources[1].nodata, Some(0.0));
        let window = mosaic.sources[1].source_window.unwrap();
        assert_eq!((window.column, window.columns), (1, 2));
    }

    #[test]
    fn a_resampling_window_is_refused_with_both_sizes() {
        let band = TWO_SOURCES.replace("xSize=\"2.0\"", "xSize=\"1\"");
        let error = parse(&vrt(&band)).unwrap_err();
        assert!(error.contains("data/tiles.vrt: source 2"), "{error}");
        assert!(error.contains("would resample"), "{error}");
    }

    #[test]
    fn unsupported_features_are_refused_by_name() {
        for (band, expected) in [
            (
                "<PixelFunctionType>sum</PixelFunctionType>",
                "<PixelFunctionType>",
            ),
            (
                "<KernelFilteredSource><SourceFilename>a.tif</SourceFilename></KernelFilteredSource>",
                "<KernelFilteredSource>",
            ),
            ("<Scale>0.1</Scale>", "height_scale"),
            (
                "<ComplexSource><SourceFilename>a.tif</SourceFilename><LUT>0:0,1:10</LUT></ComplexSource>",
                "<LUT>",
            ),
            (
                "<SimpleSource><SourceFilename>a.tif</SourceFilename><SourceBand>2</SourceBand></SimpleSource>",
                "expected 1",
            ),
            (
                "<SimpleSource><SourceFilename>/vsicurl/http://x/a.tif</SourceFilename></SimpleSource>",
                "virtual file system",
            ),
            ("", "no <SimpleSource>"),
        ] {
            let error = parse(&vrt(band)).unwrap_err();
            assert!(error.contains(expected), "{band}: {error}");
        }
        let two_bands = vrt(TWO_SOURCES).replace(
            "</VRTDataset>",
            "<VRTRasterBand band=\"2\"></VRTRasterBand></VRTDataset>",
        );
        assert!(parse(&two_bands).unwrap_err().contains("more than one"));
    }

    #[test]
    fn a_destination_outside_the_raster_is_refused() {
        let band = TWO_SOURCES.replace(
            "<DstRect xOff=\"2\" yOff=\"0\"",
            "<DstRect xOff=\"3\" yOff=\"0\"",
        );
        let error = parse(&vrt(&band)).unwrap_err();
        assert!(error.contains("reaches past the 4×3 raster"), "{error}");
    }

    #[test]
    fn a_rotated_transform_and_bad_xml_are_refused() {
        let rotated = vrt(TWO_SOURCES).replace("0.5, 0.0, 49.0", "0.5, 0.1, 49.0");
        assert!(parse(&rotated).unwrap_err().contains("north-up"));
        let error = parse("<VRTDataset rasterXSize=\"4\"").unwrap_err();
        assert!(error.contains("not well-formed XML"), "{error}");
        let error = parse("<Other/>").unwrap_err();
        assert!(error.contains("expected <VRTDataset>"), "{error}");
        let doctype = format!("<!DOCTYPE x [<!ENTITY a \"b\">]>{}", vrt(TWO_SOURCES));
        assert!(parse(&doctype).unwrap_err().contains("not well-formed"));
    }
}
