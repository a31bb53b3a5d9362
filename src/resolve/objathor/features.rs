//! The objathor feature files: CLIP image features (`img_features`, assets × views × 768),
//! CLIP text features of the descriptions (`text_features`, assets × 768, later versions) and
//! SBERT features (assets × 768), float16 as objathor writes them (float32 read as well), each with the `uids` that order its rows.
//!
//! The files' bytes are kept as read, or rows are read from the folder's index
//! (`super::stored`) when a query looks at them, and decoded then: 50,000 assets take
//! 230 MB of image features as float16 and twice that as float32.

use std::sync::Arc;

use super::pickle::{f16_to_f32, ArrayBytes};

/// The bytes a matrix of rows lies in: a file read into memory, or the folder's index, read a
/// row at a time where it lies on disk (only the rows a build looks at are read; the rest stay
/// on disk, or in the system's page cache, outside the build's memory).
#[derive(Clone)]
pub(crate) enum Backing {
    /// Bytes read (a feature file, or rows made by a test).
    Read(Arc<Vec<u8>>),
    /// The index file (`super::stored`) and its length when it was opened.
    Stored(Arc<std::fs::File>, usize),
}

impl Backing {
    /// How many bytes there are.
    pub(crate) fn len(&self) -> usize {
        match self {
            Backing::Read(bytes) => bytes.len(),
            Backing::Stored(_, len) => *len,
        }
    }

    /// The `n` bytes from byte `at`; `None` past the end, or when the file cannot be read.
    pub(crate) fn get(&self, at: usize, n: usize) -> Option<std::borrow::Cow<'_, [u8]>> {
        let end = at.checked_add(n).filter(|end| *end <= self.len())?;
        match self {
            Backing::Read(bytes) => bytes.get(at..end).map(std::borrow::Cow::Borrowed),
            Backing::Stored(file, _) => {
                let mut buf = vec![0u8; n];
                read_at(file, &mut buf, at as u64).ok()?;
                Some(std::borrow::Cow::Owned(buf))
            }
        }
    }
}

/// Reads `buf.len()` bytes of `file` from byte `at`.
#[cfg(unix)]
pub(crate) fn read_at(file: &std::fs::File, buf: &mut [u8], at: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(file, buf, at)
}

/// Reads `buf.len()` bytes of `file` from byte `at`.
#[cfg(windows)]
pub(crate) fn read_at(
    file: &std::fs::File,
    mut buf: &mut [u8],
    mut at: u64,
) -> std::io::Result<()> {
    while !buf.is_empty() {
        let n = std::os::windows::fs::FileExt::seek_read(file, buf, at)?;
        if n == 0 {
            return Err(std::io::ErrorKind::UnexpectedEof.into());
        }
        buf = &mut buf[n..];
        at += n as u64;
    }
    Ok(())
}

/// A matrix of float16 or float32 rows inside a file's bytes.
#[derive(Clone)]
pub struct FeatureRows {
    bytes: Backing,
    start: usize,
    rows: usize,
    /// Bytes per element: 2 (float16) or 4 (float32).
    item: usize,
    /// Vectors per row (views of an image row; 1 for text rows).
    pub views: usize,
    /// Length of one vector.
    pub dim: usize,
    big_endian: bool,
}

impl std::fmt::Debug for FeatureRows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = if self.item == 4 { "f4" } else { "f2" };
        write!(f, "FeatureRows({} × {} × {} {kind})", self.rows, self.views, self.dim)
    }
}

/// The float32 value of a finite float16 (normal or subnormal), without a branch: its bits
/// moved into a float32 and scaled by 2^112, both exact.
pub fn finite_f16_to_f32(h: u16) -> f32 {
    let h = u32::from(h);
    let magnitude = f32::from_bits((h & 0x7fff) << 13) * f32::from_bits(0x7780_0000);
    f32::from_bits(magnitude.to_bits() | ((h & 0x8000) << 16))
}

/// The float32 value of every float16, by bits.
fn table() -> &'static [f32] {
    static TABLE: std::sync::OnceLock<Vec<f32>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| (0..=u16::MAX).map(f16_to_f32).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_branchless_decoding_is_exact_for_every_finite_float16() {
        for h in 0..=u16::MAX {
            if h & 0x7c00 != 0x7c00 {
                assert_eq!(finite_f16_to_f32(h).to_bits(), f16_to_f32(h).to_bits(), "{h:#06x}");
            }
        }
    }

    #[test]
    fn cosines_are_those_of_the_decoded_vectors() {
        let v: Vec<f32> = (0..19).map(|i| (i as f32 - 7.0) / 8.0).collect();
        let bits: Vec<u16> = v.iter().map(|x| super::super::pickle::f32_to_f16(*x)).collect();
        let rows = FeatureRows::from_bits(&bits, 1, 1, 19);
        let mut q = vec![0f32; 19];
        q[3] = 1.0;
        let norm = v.iter().map(|x| x * x).sum::<f32>().sqrt();
        assert!((rows.cosine(&q, 0, 0) - v[3] / norm).abs() < 1e-6);
        let mut inf = bits.clone();
        inf[0] = 0x7c00;
        assert!(FeatureRows::from_bits(&inf, 1, 1, 19).cosine(&q, 0, 0).is_nan());
    }

    #[test]
    fn float32_rows_give_the_cosines_of_their_values() {
        let v: Vec<f32> = (0..19).map(|i| (i as f32 - 7.0) / 8.0 + 1e-4).collect();
        let rows = FeatureRows::from_f32(&v, 1, 1, 19);
        assert!(rows.is_f32());
        let mut q = vec![0f32; 19];
        q[3] = 1.0;
        let norm = v.iter().map(|x| x * x).sum::<f32>().sqrt();
        assert!((rows.cosine(&q, 0, 0) - v[3] / norm).abs() < 1e-6);
        let mut out = vec![0f32; 19];
        rows.decode(0, 0, &mut out);
        assert_eq!(out, v);
    }
}

impl FeatureRows {
    /// The rows of an array read from a pickle whose bytes are `file` (the bytes read, or the
    /// file itself, read a row at a time).
    pub(crate) fn new(
        file: &Backing,
        array: super::pickle::F16Array,
    ) -> Result<FeatureRows, String> {
        let (rows, views, dim) = match array.shape[..] {
            [n, v, d] => (n, v, d),
            [n, d] => (n, 1, d),
            _ => return Err(format!("its shape {:?} has neither 2 nor 3 sides", array.shape)),
        };
        if dim == 0 || views == 0 {
            return Err(format!("its shape {:?} has an empty side", array.shape));
        }
        // Every lookup indexes `start + (row · views + view) · 2 · dim`: the rows must hold
        // exactly the bytes present, counted without overflow (`Pickle::f16_array` checks the
        // same; this keeps the rows sound whatever array they are given).
        let present = array.bytes.len();
        let item = array.item;
        if !matches!(item, 2 | 4) {
            return Err(format!("its elements have {item} bytes, neither float16 nor float32"));
        }
        let needed = super::pickle::element_bytes(&[rows, views, dim], item);
        if needed != Some(present) {
            return Err(format!(
                "its shape {:?} does not match the {present} bytes it holds",
                array.shape
            ));
        }
        let (bytes, start) = match array.bytes {
            ArrayBytes::InFile(r) => (file.clone(), r.start),
            ArrayBytes::Owned(v) => (Backing::Read(Arc::new(v)), 0),
        };
        FeatureRows::within(bytes, start, [rows, views, dim], item, array.big_endian)
    }

    /// The rows of `shape` (rows, views, dim) whose elements of `item` bytes start at byte
    /// `start` of `bytes`: refused unless they lie wholly inside, counted without overflow.
    pub(crate) fn within(
        bytes: Backing,
        start: usize,
        shape: [usize; 3],
        item: usize,
        big_endian: bool,
    ) -> Result<FeatureRows, String> {
        let [rows, views, dim] = shape;
        if dim == 0 || views == 0 {
            return Err(format!("its shape {shape:?} has an empty side"));
        }
        if !matches!(item, 2 | 4) {
            return Err(format!("its elements have {item} bytes, neither float16 nor float32"));
        }
        let present = super::pickle::element_bytes(&shape, item)
            .ok_or_else(|| format!("its shape {shape:?} is too large"))?;
        if start.checked_add(present).is_none_or(|end| end > bytes.len()) {
            return Err(format!("its bytes lie outside the file ({present} from byte {start})"));
        }
        Ok(FeatureRows { bytes, start, rows, item, views, dim, big_endian })
    }

    /// The rows as they lie: the shape (rows, views, dim), the bytes per element and whether
    /// they are big-endian (what the index writes; [`FeatureRows::write_raw`] writes their
    /// bytes).
    pub(crate) fn raw(&self) -> ([usize; 3], usize, bool) {
        ([self.rows, self.views, self.dim], self.item, self.big_endian)
    }

    /// How many bytes the rows take.
    pub(crate) fn raw_len(&self) -> usize {
        self.rows * self.views * self.dim * self.item
    }

    /// Writes the rows' bytes as they lie to `out`, a few MiB at a time (rows on disk are
    /// never read whole into memory).
    ///
    /// # Errors
    /// The rows cannot be read, or `out` cannot be written.
    pub(crate) fn write_raw(&self, out: &mut impl std::io::Write) -> std::io::Result<()> {
        const STEP: usize = 4 * 1024 * 1024;
        let n = self.raw_len();
        let mut done = 0;
        while done < n {
            let take = STEP.min(n - done);
            let bytes = self
                .bytes
                .get(self.start + done, take)
                .ok_or_else(|| std::io::Error::other("the rows cannot be read"))?;
            out.write_all(&bytes)?;
            done += take;
        }
        Ok(())
    }

    /// Rows made from float16 bits (tests).
    pub fn from_bits(bits: &[u16], rows: usize, views: usize, dim: usize) -> FeatureRows {
        let bytes: Vec<u8> = bits.iter().flat_map(|b| b.to_le_bytes()).collect();
        FeatureRows {
            bytes: Backing::Read(Arc::new(bytes)),
            start: 0,
            rows,
            item: 2,
            views,
            dim,
            big_endian: false,
        }
    }

    /// Rows made from float32 values (tests).
    pub fn from_f32(values: &[f32], rows: usize, views: usize, dim: usize) -> FeatureRows {
        let bytes: Vec<u8> = values.iter().flat_map(|b| b.to_le_bytes()).collect();
        FeatureRows {
            bytes: Backing::Read(Arc::new(bytes)),
            start: 0,
            rows,
            item: 4,
            views,
            dim,
            big_endian: false,
        }
    }

    /// The bytes the rows lie in.
    #[cfg(test)]
    pub(crate) fn backing(&self) -> &Backing {
        &self.bytes
    }

    /// Whether the rows are float32 (else float16).
    pub fn is_f32(&self) -> bool {
        self.item == 4
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.rows
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// One vector's bytes. A vector of an index that cannot be read (the file cut short
    /// under a running build, a disk error) reads as NaNs, which no score passes.
    fn vector_bytes(&self, row: usize, view: usize) -> std::borrow::Cow<'_, [u8]> {
        let n = self.item * self.dim;
        let at = self.start + (row * self.views + view) * n;
        self.bytes.get(at, n).unwrap_or_else(|| {
            let nan: &[u8] = if self.item == 4 { &[0, 0, 0xc0, 0x7f] } else { &[0, 0x7e] };
            let nan: Vec<u8> =
                if self.big_endian { nan.iter().rev().copied().collect() } else { nan.to_vec() };
            std::borrow::Cow::Owned(nan.repeat(self.dim))
        })
    }

    /// Decodes one vector into `out` (of length `dim`).
    pub fn decode(&self, row: usize, view: usize, out: &mut [f32]) {
        let big = self.big_endian;
        if self.item == 4 {
            for (o, c) in out.iter_mut().zip(self.vector_bytes(row, view).chunks_exact(4)) {
                let b = [c[0], c[1], c[2], c[3]];
                *o = if big { f32::from_be_bytes(b) } else { f32::from_le_bytes(b) };
            }
            return;
        }
        let t = table();
        for (o, c) in out.iter_mut().zip(self.vector_bytes(row, view).chunks_exact(2)) {
            let b = [c[0], c[1]];
            *o = t[usize::from(if big { u16::from_be_bytes(b) } else { u16::from_le_bytes(b) })];
        }
    }

    /// The cosine between a unit vector `q` and one vector of a row (0 for a zero vector).
    /// Eight running sums in a fixed order: the same result on every machine (the compiler
    /// may run the eight at once; it never reorders a sum).
    pub fn cosine(&self, q: &[f32], row: usize, view: usize) -> f32 {
        if self.item == 4 {
            return self.cosine_f32(q, row, view);
        }
        let bytes = self.vector_bytes(row, view);
        // A query shorter than a row (never from `rank`, which sizes it by the rows) counts
        // only the elements it has.
        let bytes = &bytes[..bytes.len().min(2 * q.len())];
        let big = self.big_endian;
        let bits = |c: &[u8]| {
            let b = [c[0], c[1]];
            if big {
                u16::from_be_bytes(b)
            } else {
                u16::from_le_bytes(b)
            }
        };
        // Infinities and NaNs (never in real feature files) and big-endian files take the
        // exact table, one element at a time; the rest the branchless decoding, eight at once.
        let special = big || bytes.chunks_exact(2).any(|c| bits(c) & 0x7c00 == 0x7c00);
        let mut dot = [0f32; 8];
        let mut sq = [0f32; 8];
        let (mut blocks, mut qs) = (bytes.chunks_exact(16), q.chunks_exact(8));
        if !special {
            for (block, qb) in (&mut blocks).zip(&mut qs) {
                let (Ok(block), Ok(qb)) = (<&[u8; 16]>::try_from(block), <&[f32; 8]>::try_from(qb))
                else {
                    continue;
                };
                let mut v = [0f32; 8];
                for (i, x) in v.iter_mut().enumerate() {
                    *x = finite_f16_to_f32(u16::from_le_bytes([block[2 * i], block[2 * i + 1]]));
                }
                for i in 0..8 {
                    dot[i] += v[i] * qb[i];
                    sq[i] += v[i] * v[i];
                }
            }
        }
        // What is left (all of it on the exact path), each element in its lane.
        let done = (bytes.len() / 16 - blocks.len()) * 8;
        let t = table();
        for (k, (c, qv)) in bytes[2 * done..].chunks_exact(2).zip(&q[done..]).enumerate() {
            let v = t[usize::from(bits(c))];
            dot[k % 8] += v * qv;
            sq[k % 8] += v * v;
        }
        lanes_cosine(&dot, &sq)
    }

    /// [`FeatureRows::cosine`] of float32 rows: the same eight lanes.
    fn cosine_f32(&self, q: &[f32], row: usize, view: usize) -> f32 {
        let bytes = self.vector_bytes(row, view);
        let bytes = &bytes[..bytes.len().min(4 * q.len())];
        let big = self.big_endian;
        let mut dot = [0f32; 8];
        let mut sq = [0f32; 8];
        for (k, (c, qv)) in bytes.chunks_exact(4).zip(q).enumerate() {
            let b = [c[0], c[1], c[2], c[3]];
            let v = if big { f32::from_be_bytes(b) } else { f32::from_le_bytes(b) };
            dot[k % 8] += v * qv;
            sq[k % 8] += v * v;
        }
        lanes_cosine(&dot, &sq)
    }

    /// The largest cosine over a row's views.
    pub fn max_cosine(&self, q: &[f32], row: usize) -> f32 {
        (0..self.views).map(|v| self.cosine(q, row, v)).fold(f32::NEG_INFINITY, f32::max)
    }

    /// Adds the unit vectors of a row's views, averaged, to `sum`.
    pub fn add_unit_mean(&self, row: usize, sum: &mut [f32]) {
        let mut v = vec![0f32; self.dim];
        for view in 0..self.views {
            self.decode(row, view, &mut v);
            normalize(&mut v);
            for (s, x) in sum.iter_mut().zip(&v) {
                *s += x / self.views as f32;
            }
        }
    }
}

/// The cosine of a unit query and a vector from their eight lanes of dot products and of the
/// vector's squares, summed in a fixed order (0 for a zero vector).
fn lanes_cosine(dot: &[f32; 8], sq: &[f32; 8]) -> f32 {
    let dot: f32 = dot.iter().sum();
    let sq: f32 = sq.iter().sum();
    if sq > 0.0 {
        dot / sq.sqrt()
    } else {
        0.0
    }
}

/// Scales `v` to unit length (a zero vector stays zero).
pub fn normalize(v: &mut [f32]) {
    let n: f32 = v.iter().map(|x| x * x).sum::<f32>().sqrt();
    if n > 0.0 {
        for x in v.iter_mut() {
            *x /= n;
        }
    }
}

/// The feature rows of one version folder, each with the asset it belongs to.
#[derive(Clone, Debug, Default)]
pub struct Features {
    /// CLIP image features (views × dim per row).
    pub img: Option<FeatureRows>,
    /// CLIP text features of the descriptions.
    pub text: Option<FeatureRows>,
    /// SBERT features of the descriptions.
    pub sbert: Option<FeatureRows>,
    /// Per objathor asset (by its place in the folder's range): its CLIP row, or `u32::MAX`.
    pub clip_row: Vec<u32>,
    /// Per objathor asset: its SBERT row, or `u32::MAX`.
    pub sbert_row: Vec<u32>,
}

impl Features {
    /// The CLIP row of the `k`-th asset of the folder.
    pub fn clip_row_of(&self, k: usize) -> Option<usize> {
        self.clip_row.get(k).filter(|r| **r != u32::MAX).map(|r| *r as usize)
    }

    /// The SBERT row of the `k`-th asset of the folder.
    pub fn sbert_row_of(&self, k: usize) -> Option<usize> {
        self.sbert_row.get(k).filter(|r| **r != u32::MAX).map(|r| *r as usize)
    }
}
