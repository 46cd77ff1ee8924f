//! An exact encoding of one frame's statistics ([`FrameStats`]) as a flat list of 64-bit words,
//! for shard files (`shard.json`): every count as itself, every `f64` as its bit pattern (so
//! NaN, infinities and the last bit survive JSON), every `Option` as a presence word (0 or 1)
//! followed by its value when present. Decoding is the exact inverse; a list that is too short
//! or too long is refused.
//!
//! Not a file format of its own: the words are only ever read by the same build that wrote them
//! (the shard file records its format version, and `merge` refuses another).

use crate::sim::stats::{
    AuditFrame, ErrorSummary, FrameStats, MeshCounts, PoppingFrame, SurfaceCoverage,
};

/// The words of one frame.
pub fn encode_frame(stats: &FrameStats) -> Vec<u64> {
    // Destructured so that a new field is a compile error here, not a silently dropped value.
    let FrameStats {
        frame,
        triangles,
        triangles_rendered,
        splits,
        merges,
        vertices_inserted,
        vertices_deleted,
        metric_evaluations,
        update_ns,
        frame_ns,
        upload_bytes,
        draw_calls,
        triangles_submitted,
        extra,
        mesh,
        audit,
        audit_detail,
    } = stats;
    let mut words = vec![
        *frame,
        *triangles,
        *triangles_rendered,
        *splits,
        *merges,
        *vertices_inserted,
        *vertices_deleted,
        *metric_evaluations,
        *update_ns,
        *frame_ns,
        *upload_bytes,
        *draw_calls,
        *triangles_submitted,
        extra.len() as u64,
    ];
    words.extend(extra.iter().map(|value| value.to_bits()));
    push_option(&mut words, mesh.as_ref(), |words, mesh| {
        let MeshCounts {
            triangles_by_role,
            morphing_vertices,
        } = mesh;
        words.extend(triangles_by_role);
        words.push(*morphing_vertices);
    });
    push_option(&mut words, audit.as_ref(), push_audit);
    push_option(&mut words, audit_detail.as_ref(), push_audit);
    words
}

/// The frame the words encode; `None` when they are not a whole encoded frame.
pub fn decode_frame(words: &[u64]) -> Option<FrameStats> {
    let mut reader = Reader { words, at: 0 };
    let mut counts = [0u64; 13];
    for count in &mut counts {
        *count = reader.word()?;
    }
    let n_extra = usize::try_from(reader.word()?).ok()?;
    if n_extra > words.len() {
        return None;
    }
    let extra = (0..n_extra)
        .map(|_| reader.float())
        .collect::<Option<Vec<f64>>>()?;
    let mesh = reader.option(|r| {
        Some(MeshCounts {
            triangles_by_role: [r.word()?, r.word()?, r.word()?, r.word()?],
            morphing_vertices: r.word()?,
        })
    })?;
    let audit = reader.option(read_audit)?;
    let audit_detail = reader.option(read_audit)?;
    if reader.at != words.len() {
        return None;
    }
    let [
        frame,
        triangles,
        triangles_rendered,
        splits,
        merges,
        vertices_inserted,
        vertices_deleted,
        metric_evaluations,
        update_ns,
        frame_ns,
        upload_bytes,
        draw_calls,
        triangles_submitted,
    ] = counts;
    Some(FrameStats {
        frame,
        triangles,
        triangles_rendered,
        splits,
        merges,
        vertices_inserted,
        vertices_deleted,
        metric_evaluations,
        update_ns,
        frame_ns,
        upload_bytes,
        draw_calls,
        triangles_submitted,
        extra,
        mesh,
        audit,
        audit_detail,
    })
}

fn push_option<T>(words: &mut Vec<u64>, value: Option<&T>, push: impl FnOnce(&mut Vec<u64>, &T)) {
    match value {
        Some(value) => {
            words.push(1);
            push(words, value);
        }
        None => words.push(0),
    }
}

fn push_floats(words: &mut Vec<u64>, values: &[f64]) {
    words.extend(values.iter().map(|v| v.to_bits()));
}

fn push_audit(words: &mut Vec<u64>, audit: &AuditFrame) {
    let AuditFrame {
        samples_in_view,
        projected,
        view_angle,
        coverage,
        popping,
    } = audit;
    words.push(*samples_in_view);
    for summary in [projected, view_angle] {
        push_option(words, summary.as_ref(), |words, s| {
            let ErrorSummary { max, mean, p95 } = s;
            push_floats(words, &[*max, *mean, *p95]);
        });
    }
    push_option(words, coverage.as_ref(), |words, c| {
        let SurfaceCoverage {
            holes,
            crack_samples,
            crack_gap_max_m,
            crack_gap_max_px,
            cracks_uncovered,
            crack_uncovered_max_m,
            crack_uncovered_max_px,
        } = c;
        words.extend([*holes, *crack_samples]);
        push_floats(words, &[*crack_gap_max_m, *crack_gap_max_px]);
        words.push(*cracks_uncovered);
        push_floats(words, &[*crack_uncovered_max_m, *crack_uncovered_max_px]);
    });
    push_option(words, popping.as_ref(), |words, p| {
        let PoppingFrame {
            samples,
            rmse_m,
            max_m,
            rmse_px,
            max_px,
        } = p;
        words.push(*samples);
        push_floats(words, &[*rmse_m, *max_m, *rmse_px, *max_px]);
    });
}

fn read_audit(r: &mut Reader) -> Option<AuditFrame> {
    let samples_in_view = r.word()?;
    let summary = |r: &mut Reader| {
        r.option(|r| {
            Some(ErrorSummary {
                max: r.float()?,
                mean: r.float()?,
                p95: r.float()?,
            })
        })
    };
    let projected = summary(r)?;
    let view_angle = summary(r)?;
    let coverage = r.option(|r| {
        Some(SurfaceCoverage {
            holes: r.word()?,
            crack_samples: r.word()?,
            crack_gap_max_m: r.float()?,
            crack_gap_max_px: r.float()?,
            cracks_uncovered: r.word()?,
            crack_uncovered_max_m: r.float()?,
            crack_uncovered_max_px: r.float()?,
        })
    })?;
    let popping = r.option(|r| {
        Some(PoppingFrame {
            samples: r.word()?,
            rmse_m: r.float()?,
            max_m: r.float()?,
            rmse_px: r.float()?,
            max_px: r.float()?,
        })
    })?;
    Some(AuditFrame {
        samples_in_view,
        projected,
        view_angle,
        coverage,
        popping,
    })
}

/// Reads words in order; `None` past the end.
struct Reader<'a> {
    words: &'a [u64],
    at: usize,
}

impl Reader<'_> {
    fn word(&mut self) -> Option<u64> {
        let word = *self.words.get(self.at)?;
        self.at += 1;
        Some(word)
    }

    fn float(&mut self) -> Option<f64> {
        self.word().map(f64::from_bits)
    }

    /// A presence word, then the value when it is 1: `Some(None)` for an absent value, `None`
    /// for a malformed list.
    fn option<T>(&mut self, read: impl FnOnce(&mut Self) -> Option<T>) -> Option<Option<T>> {
        match self.word()? {
            0 => Some(None),
            1 => read(self).map(Some),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn any_float() -> impl Strategy<Value = f64> {
        prop_oneof![
            any::<f64>(),
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(-0.0),
            Just(0.1 + 0.2),
        ]
    }

    fn summary() -> impl Strategy<Value = Option<ErrorSummary>> {
        proptest::option::of(
            (any_float(), any_float(), any_float()).prop_map(|(max, mean, p95)| ErrorSummary {
                max,
                mean,
                p95,
            }),
        )
    }

    fn audit() -> impl Strategy<Value = AuditFrame> {
        let coverage = proptest::option::of(
            (
                any::<u64>(),
                any::<u64>(),
                any_float(),
                any_float(),
                any::<u64>(),
                any_float(),
                any_float(),
            )
                .prop_map(|(a, b, c, d, e, f, g)| SurfaceCoverage {
                    holes: a,
                    crack_samples: b,
                    crack_gap_max_m: c,
                    crack_gap_max_px: d,
                    cracks_uncovered: e,
                    crack_uncovered_max_m: f,
                    crack_uncovered_max_px: g,
                }),
        );
        let popping = proptest::option::of(
            (
                any::<u64>(),
                any_float(),
                any_float(),
                any_float(),
                any_float(),
            )
                .prop_map(|(samples, rmse_m, max_m, rmse_px, max_px)| PoppingFrame {
                    samples,
                    rmse_m,
                    max_m,
                    rmse_px,
                    max_px,
                }),
        );
        (any::<u64>(), summary(), summary(), coverage, popping).prop_map(
            |(samples_in_view, projected, view_angle, coverage, popping)| AuditFrame {
                samples_in_view,
                projected,
                view_angle,
                coverage,
                popping,
            },
        )
    }

    fn frame() -> impl Strategy<Value = FrameStats> {
        let mesh = proptest::option::of((any::<[u64; 4]>(), any::<u64>()).prop_map(
            |(roles, morph)| MeshCounts {
                triangles_by_role: roles,
                morphing_vertices: morph,
            },
        ));
        (
            any::<[u64; 13]>(),
            proptest::collection::vec(any_float(), 0..6),
            mesh,
            proptest::option::of(audit()),
            proptest::option::of(audit()),
        )
            .prop_map(|(c, extra, mesh, audit, audit_detail)| FrameStats {
                frame: c[0],
                triangles: c[1],
                triangles_rendered: c[2],
                splits: c[3],
                merges: c[4],
                vertices_inserted: c[5],
                vertices_deleted: c[6],
                metric_evaluations: c[7],
                update_ns: c[8],
                frame_ns: c[9],
                upload_bytes: c[10],
                draw_calls: c[11],
                triangles_submitted: c[12],
                extra,
                mesh,
                audit,
                audit_detail,
            })
    }

    /// Bit-level equality (NaN equals itself), through the encoding.
    fn same(a: &FrameStats, b: &FrameStats) -> bool {
        encode_frame(a) == encode_frame(b) && format!("{a:?}") == format!("{b:?}")
    }

    proptest! {
        #[test]
        fn every_frame_decodes_to_itself_bit_for_bit(stats in frame()) {
            let words = encode_frame(&stats);
            let back = decode_frame(&words).expect("a whole frame");
            prop_assert!(same(&stats, &back), "{stats:?} came back as {back:?}");
        }

        #[test]
        fn a_cut_or_padded_frame_is_refused(stats in frame(), cut in 1usize..8) {
            let words = encode_frame(&stats);
            let cut = cut.min(words.len());
            prop_assert!(decode_frame(&words[..words.len() - cut]).is_none());
            let mut padded = words.clone();
            padded.push(0);
            prop_assert!(decode_frame(&padded).is_none());
        }
    }

    #[test]
    fn a_presence_word_other_than_0_or_1_is_refused() {
        let mut words = encode_frame(&FrameStats::default());
        // The last word is the detail audit's presence word (absent: 0).
        *words.last_mut().expect("words") = 2;
        assert!(decode_frame(&words).is_none());
    }
}
