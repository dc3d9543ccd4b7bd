//! The inverse-model workbench's images: a model's evidence over a beam's
//! neighbourhood (range × bearing) on a gray scale shared by both models,
//! white free, mid-gray no evidence, black occupied (the maps' convention).

use crate::error::{OccError, Result};

/// Draws `field` (`bearings` rows of `ranges` evidence values, log odds,
/// the first row at the most negative bearing) into RGBA pixels with the
/// most positive bearing on top: gray `128 - 127 e / scale`, clamped, so
/// that `+scale` is black and `-scale` white. A scale of 0 draws mid-gray.
pub fn render_evidence_rgba(
    field: &[f32],
    ranges: usize,
    bearings: usize,
    scale: f64,
    out: &mut Vec<u8>,
) -> Result<()> {
    if field.len() != ranges * bearings {
        return Err(OccError::LengthMismatch {
            field: "evidence field".into(),
            expected: ranges * bearings,
            found: field.len(),
        });
    }
    let s = if scale > 0.0 { 127.0 / scale } else { 0.0 };
    out.clear();
    out.resize(field.len() * 4, 255);
    for j in 0..bearings {
        let row = bearings - 1 - j;
        for i in 0..ranges {
            let e = field[j * ranges + i] as f64;
            let g = (128.0 - e * s).round().clamp(0.0, 255.0) as u8;
            let k = 4 * (row * ranges + i);
            out[k..k + 3].fill(g);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_maps_plus_scale_to_black_and_the_top_row_to_the_last_bearing() {
        // Two bearings, two ranges: row 0 (first bearing) [-2, 0], row 1 [2, 1].
        let field = [-2.0, 0.0, 2.0, 1.0];
        let mut px = Vec::new();
        render_evidence_rgba(&field, 2, 2, 2.0, &mut px).unwrap();
        // The top image row is the last bearing.
        assert_eq!((px[0], px[4]), (1, 65), "black at +scale, 128 - 63.5 at +1");
        assert_eq!(
            (px[8], px[12]),
            (255, 128),
            "white at -scale, mid-gray at 0"
        );
        assert_eq!(px[3], 255);
        assert!(render_evidence_rgba(&field, 3, 2, 2.0, &mut px).is_err());
    }
}
