//! The PNG every figure draws on, with its font inside the program: the labels render the
//! same on every platform the harness ships for, and the harness needs no fontconfig,
//! FreeType or installed font (DejaVu Sans, `report/fonts/`, Bitstream Vera licence).
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::Path;
use std::sync::Once;

const SANS: &[u8] = include_bytes!("../../fonts/DejaVuSans.ttf");

/// A PNG of `size` pixels at `path`, the embedded font registered as "sans-serif".
pub fn bitmap(
    path: &Path,
    size: (u32, u32),
) -> DrawingArea<BitMapBackend<'_>, plotters::coord::Shift> {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // A font that does not parse is a build defect: every figure test would show it.
        if register_font("sans-serif", FontStyle::Normal, SANS).is_err() {
            unreachable!("the embedded DejaVu Sans does not parse");
        }
    });
    BitMapBackend::new(path, size).into_drawing_area()
}
