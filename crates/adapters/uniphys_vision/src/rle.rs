//! Uncompressed COCO run-length encoding: runs alternate background / foreground, starting with
//! background, over the pixels in column-major order (down each column, then the next column).

use serde::{Deserialize, Serialize};

/// An uncompressed COCO RLE mask.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rle {
    /// `[height, width]` in pixels (COCO order).
    pub size: [u32; 2],
    /// Run lengths, alternating background and foreground, the first one background (may be 0).
    pub counts: Vec<u64>,
}

impl Rle {
    /// Encodes a row-major mask of `width_px x height_px` pixels.
    ///
    /// # Panics
    /// Never; a `pixels` shorter than the image counts the missing pixels as background.
    #[must_use]
    pub fn encode(width_px: u32, height_px: u32, pixels: &[bool]) -> Self {
        let (width, height) = (width_px as usize, height_px as usize);
        let mut counts = Vec::new();
        let mut current = false;
        let mut run = 0u64;
        for x in 0..width {
            for y in 0..height {
                let value = pixels.get(y * width + x).copied().unwrap_or(false);
                if value != current {
                    counts.push(run);
                    run = 0;
                    current = value;
                }
                run += 1;
            }
        }
        counts.push(run);
        Self {
            size: [height_px, width_px],
            counts,
        }
    }

    /// Decodes to a row-major mask of `width_px x height_px` pixels.
    ///
    /// # Errors
    /// A message if the size differs from the image or the runs do not cover it exactly.
    pub fn decode(&self, width_px: u32, height_px: u32) -> Result<Vec<bool>, String> {
        if self.size != [height_px, width_px] {
            return Err(format!(
                "RLE size [h, w] = {:?} but the image is [{height_px}, {width_px}]",
                self.size
            ));
        }
        let (width, height) = (width_px as usize, height_px as usize);
        let pixel_count = (width as u64) * (height as u64);
        let total = self
            .counts
            .iter()
            .try_fold(0u64, |sum, &run| sum.checked_add(run))
            .ok_or_else(|| "RLE run lengths overflow".to_owned())?;
        if total != pixel_count {
            return Err(format!(
                "RLE runs sum to {total} pixels but the image has h*w = {pixel_count}"
            ));
        }
        let mut pixels = vec![false; width * height];
        let mut position = 0usize;
        for (index, &run) in self.counts.iter().enumerate() {
            let run = run as usize;
            if index % 2 == 1 {
                for column_major in position..position + run {
                    let (x, y) = (column_major / height, column_major % height);
                    pixels[y * width + x] = true;
                }
            }
            position += run;
        }
        Ok(pixels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_non_square_mask_survives_encode_decode_in_column_major_order() {
        // 3 wide, 2 high; foreground = the top row's first two pixels and the bottom-right one.
        let pixels = [true, true, false, false, false, true];
        let rle = Rle::encode(3, 2, &pixels);
        // Column-major order: (0,0)=1 (0,1)=0 (1,0)=1 (1,1)=0 (2,0)=0 (2,1)=1.
        assert_eq!(rle.counts, vec![0, 1, 1, 1, 2, 1]);
        assert_eq!(rle.size, [2, 3]);
        assert_eq!(rle.decode(3, 2).unwrap(), pixels);
    }

    #[test]
    fn wrong_size_or_wrong_sum_is_refused() {
        let rle = Rle {
            size: [2, 3],
            counts: vec![2, 3],
        };
        assert!(rle.decode(3, 2).unwrap_err().contains("sum to 5"));
        assert!(rle.decode(2, 3).unwrap_err().contains("size"));
        let overflow = Rle {
            size: [2, 3],
            counts: vec![u64::MAX, 7],
        };
        assert!(overflow.decode(3, 2).is_err());
    }
}
