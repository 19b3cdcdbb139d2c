//! Colour reduction of a drawn frame to a GIF palette (≤ 256 colours) by popularity.
//!
//! The frames are flat fills (bodies, one colour each per depth), lines and anti-aliased text: a
//! few dozen colours cover almost every pixel, and the rest are the grey edges of glyphs. So the
//! palette is the (up to) 256 most frequent colours, exact; every other colour maps to its
//! nearest palette colour (squared RGB distance, ties to the more frequent). A frame with at most
//! 256 colours is reproduced exactly. This costs two passes over the pixels with a cache of the
//! last colour (runs are long), instead of NeuQuant's training: measured in `benches/render.rs`.

use std::collections::HashMap;

/// Palette (RGB triples, at most 256) and one palette index per pixel of the RGB buffer `rgb`
/// (3 bytes per pixel).
///
/// ```
/// use helixreach::plot::render::palette::reduce;
/// let rgb = [255, 255, 255, 255, 255, 255, 10, 20, 30];
/// let (pal, idx) = reduce(&rgb);
/// assert_eq!(pal, vec![255, 255, 255, 10, 20, 30]);
/// assert_eq!(idx, vec![0, 0, 1]);
/// ```
pub fn reduce(rgb: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let key = |p: &[u8]| (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32;
    // Pass 1: colour counts, by runs.
    let mut counts: HashMap<u32, usize> = HashMap::new();
    let mut last = u32::MAX;
    let mut run = 0usize;
    for p in rgb.chunks_exact(3) {
        let k = key(p);
        if k == last {
            run += 1;
        } else {
            if run > 0 {
                *counts.entry(last).or_insert(0) += run;
            }
            last = k;
            run = 1;
        }
    }
    if run > 0 {
        *counts.entry(last).or_insert(0) += run;
    }
    let mut by_count: Vec<(u32, usize)> = counts.into_iter().collect();
    // Most frequent first; ties by colour, so the palette is deterministic.
    by_count.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    by_count.truncate(256);
    let palette: Vec<u32> = by_count.iter().map(|c| c.0).collect();
    let mut index: HashMap<u32, u8> = palette
        .iter()
        .enumerate()
        .map(|(i, &c)| (c, i as u8))
        .collect();
    let split = |c: u32| [(c >> 16) as i32, (c >> 8 & 0xff) as i32, (c & 0xff) as i32];
    let nearest = |c: u32| -> u8 {
        let a = split(c);
        let mut best = (i32::MAX, 0u8);
        for (i, &p) in palette.iter().enumerate() {
            let b = split(p);
            let d = (a[0] - b[0]).pow(2) + (a[1] - b[1]).pow(2) + (a[2] - b[2]).pow(2);
            if d < best.0 {
                best = (d, i as u8);
            }
        }
        best.1
    };
    // Pass 2: indices, with the last colour cached.
    let mut out = Vec::with_capacity(rgb.len() / 3);
    let (mut last, mut last_i) = (u32::MAX, 0u8);
    for p in rgb.chunks_exact(3) {
        let k = key(p);
        if k != last {
            last = k;
            last_i = match index.get(&k) {
                Some(&i) => i,
                None => {
                    let i = nearest(k);
                    index.insert(k, i);
                    i
                }
            };
        }
        out.push(last_i);
    }
    let pal = palette
        .iter()
        .flat_map(|&c| split(c).map(|v| v as u8))
        .collect();
    (pal, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_colours_exact_many_colours_nearest() {
        // 300 distinct greys, grey g repeated (300 − g) times: the 256 most frequent are kept
        // exactly; the 44 rarest (g = 256..299) map to the nearest kept grey, g = 255.
        let mut rgb = Vec::new();
        for g in 0..300u32 {
            let v = (g * 255 / 299) as u8;
            let c = [v, v, (g % 256) as u8];
            for _ in 0..(300 - g) {
                rgb.extend_from_slice(&c);
            }
        }
        let (pal, idx) = reduce(&rgb);
        assert_eq!(pal.len(), 256 * 3);
        let mut max_err = 0;
        for (p, &i) in rgb.chunks_exact(3).zip(&idx) {
            let q = &pal[3 * i as usize..3 * i as usize + 3];
            let e: i32 = (0..3).map(|k| (p[k] as i32 - q[k] as i32).pow(2)).sum();
            max_err = max_err.max(e);
        }
        // Brute force: the error of each colour is the distance to its nearest palette colour.
        assert!(max_err > 0);
        for (p, &i) in rgb.chunks_exact(3).zip(&idx) {
            let q = &pal[3 * i as usize..3 * i as usize + 3];
            let e: i32 = (0..3).map(|k| (p[k] as i32 - q[k] as i32).pow(2)).sum();
            let best = pal
                .chunks_exact(3)
                .map(|q| {
                    (0..3)
                        .map(|k| (p[k] as i32 - q[k] as i32).pow(2))
                        .sum::<i32>()
                })
                .min()
                .unwrap();
            assert_eq!(e, best);
        }
        // ≤ 256 colours: exact.
        let small: Vec<u8> = rgb[..3 * 5000].to_vec();
        let (pal, idx) = reduce(&small);
        for (p, &i) in small.chunks_exact(3).zip(&idx) {
            assert_eq!(p, &pal[3 * i as usize..3 * i as usize + 3]);
        }
    }
}
