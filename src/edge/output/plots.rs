//! Placeholder: line charts are being written.
