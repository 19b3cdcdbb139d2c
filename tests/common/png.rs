//! A decoded 8-bit PNG (RGB or RGBA, alpha dropped) for the figure tests, with the pixel
//! statistics they assert on.
#![allow(dead_code)]

use std::collections::HashSet;
use std::path::Path;

/// Pixels row by row, top to bottom.
pub struct Png {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[u8; 3]>,
}

impl Png {
    /// Decode `path`; panics (naming the file) on anything but an 8-bit RGB/RGBA PNG.
    pub fn read(path: &Path) -> Png {
        let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut dec = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut buf = vec![0; dec.output_buffer_size()];
        let info = dec
            .next_frame(&mut buf)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let ch = match info.color_type {
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            other => panic!("{}: unexpected PNG colour type {other:?}", path.display()),
        };
        assert_eq!(info.bit_depth, png::BitDepth::Eight, "{}", path.display());
        Png {
            width: info.width,
            height: info.height,
            rgb: buf[..info.buffer_size()]
                .chunks(ch)
                .map(|p| [p[0], p[1], p[2]])
                .collect(),
        }
    }

    /// Share of pixels that are not pure white.
    pub fn non_white_fraction(&self) -> f64 {
        self.rgb.iter().filter(|p| **p != [255, 255, 255]).count() as f64 / self.rgb.len() as f64
    }

    /// Number of distinct colours.
    pub fn distinct_colours(&self) -> usize {
        self.rgb.iter().collect::<HashSet<_>>().len()
    }

    /// Number of pixels of exactly colour `c`.
    pub fn count(&self, c: [u8; 3]) -> usize {
        self.rgb.iter().filter(|p| **p == c).count()
    }

    /// The pixel at (x, y); panics outside the image.
    pub fn at(&self, p: (i32, i32)) -> [u8; 3] {
        assert!(p.0 >= 0 && p.1 >= 0 && (p.0 as u32) < self.width && (p.1 as u32) < self.height);
        self.rgb[p.1 as usize * self.width as usize + p.0 as usize]
    }
}
