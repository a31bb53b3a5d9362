//! Triangle meshes for the glTF export: boxes, wall slabs with holes, floor and ceiling
//! polygons. Every vertex has its own normal (flat shading); triangles are counter-clockwise
//! seen from the side their normal points to, as glTF wants.

use nalgebra::{Isometry3, Point3, Vector3};

/// One primitive's geometry: positions, normals and triangle indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Triangles, three indices each.
    pub indices: Vec<u32>,
}

/// Extents shorter than this (metres) make no box: a degenerate face would only trouble
/// viewers.
const MIN_EXTENT_M: f64 = 1e-4;

impl Geometry {
    /// Whether it holds no triangle.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// Adds a triangle of three `(position, normal)` corners, counter-clockwise seen from
    /// outside.
    pub fn push_triangle(&mut self, corners: impl Iterator<Item = ([f64; 3], [f64; 3])>) {
        let base = self.positions.len() as u32;
        let mut n = 0;
        for (p, normal) in corners.take(3) {
            self.positions.push([p[0] as f32, p[1] as f32, p[2] as f32]);
            self.normals.push([normal[0] as f32, normal[1] as f32, normal[2] as f32]);
            n += 1;
        }
        if n == 3 {
            self.indices.extend([base, base + 1, base + 2]);
        } else {
            self.positions.truncate(base as usize);
            self.normals.truncate(base as usize);
        }
    }

    /// Adds a quad `a b c d` (counter-clockwise seen from `normal`).
    fn quad(&mut self, corners: [Point3<f64>; 4], normal: Vector3<f64>) {
        let base = self.positions.len() as u32;
        let n = normal.normalize();
        for c in corners {
            self.positions.push([c.x as f32, c.y as f32, c.z as f32]);
            self.normals.push([n.x as f32, n.y as f32, n.z as f32]);
        }
        self.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }

    /// Adds the box `min..max` (in its own frame), placed by `pose`. A box thinner than 0.1 mm
    /// in any direction is left out.
    pub fn add_box(&mut self, min: [f64; 3], max: [f64; 3], pose: &Isometry3<f64>) {
        if (0..3).any(|i| max[i] - min[i] < MIN_EXTENT_M) {
            return;
        }
        let p = |x: usize, y: usize, z: usize| {
            let local = Point3::new(
                if x == 0 { min[0] } else { max[0] },
                if y == 0 { min[1] } else { max[1] },
                if z == 0 { min[2] } else { max[2] },
            );
            pose * local
        };
        let r = |v: Vector3<f64>| pose.rotation * v;
        // +x, -x, +y, -y, +z, -z; each quad counter-clockwise seen from outside.
        self.quad([p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)], r(Vector3::x()));
        self.quad([p(0, 0, 1), p(0, 1, 1), p(0, 1, 0), p(0, 0, 0)], r(-Vector3::x()));
        self.quad([p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)], r(Vector3::y()));
        self.quad([p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)], r(-Vector3::y()));
        self.quad([p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)], r(Vector3::z()));
        self.quad([p(0, 1, 0), p(1, 1, 0), p(1, 0, 0), p(0, 0, 0)], r(-Vector3::z()));
    }

    /// Adds a horizontal polygon (points `[x, z]`) at height `y`, facing up or down,
    /// triangulated with earcut. Returns `false` when the outline cannot be triangulated.
    pub fn add_polygon(&mut self, outline: &[[f64; 2]], y: f64, up: bool) -> bool {
        let flat: Vec<f64> = outline.iter().flat_map(|p| [p[0], p[1]]).collect();
        let Ok(triangles) = earcutr::earcut(&flat, &[], 2) else {
            return false;
        };
        if triangles.is_empty() {
            return false;
        }
        let base = self.positions.len() as u32;
        let normal = if up { [0.0, 1.0, 0.0] } else { [0.0, -1.0, 0.0] };
        for p in outline {
            self.positions.push([p[0] as f32, y as f32, p[1] as f32]);
            self.normals.push(normal);
        }
        for t in triangles.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]];
            // Seen from above (+y) with x right, +z points down the screen in a right-handed
            // frame: a triangle faces up when (b - a) × (c - a) has a positive y.
            let (pa, pb, pc) = (outline[a], outline[b], outline[c]);
            let cross_y = (pb[1] - pa[1]) * (pc[0] - pa[0]) - (pb[0] - pa[0]) * (pc[1] - pa[1]);
            let faces_up = cross_y > 0.0;
            let (b, c) = if faces_up == up { (b, c) } else { (c, b) };
            self.indices.extend([base + a as u32, base + b as u32, base + c as u32]);
        }
        true
    }

    /// The smallest and largest position on each axis (`None` when empty).
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        let mut min = first;
        let mut max = first;
        for p in &self.positions {
            for i in 0..3 {
                min[i] = min[i].min(p[i]);
                max[i] = max[i].max(p[i]);
            }
        }
        Some((min, max))
    }
}

/// A hole in a wall, in the wall's frame: along the wall from its start, and up from the floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hole {
    /// Start and end along the wall, metres.
    pub x: [f64; 2],
    /// Bottom and top, metres.
    pub y: [f64; 2],
}

/// Adds a wall slab `0..length` × `0..height` × `z` to `geometry` (in the wall's frame) with the
/// holes cut out: the slab is cut into columns at every hole's sides, and each column keeps
/// what no hole covers.
pub fn add_wall_slab(
    geometry: &mut Geometry,
    length: f64,
    height: f64,
    z: [f64; 2],
    holes: &[Hole],
) {
    let mut cuts = vec![0.0, length];
    for h in holes {
        cuts.extend([h.x[0].clamp(0.0, length), h.x[1].clamp(0.0, length)]);
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() < MIN_EXTENT_M);
    let identity = Isometry3::identity();
    for pair in cuts.windows(2) {
        let (x0, x1) = (pair[0], pair[1]);
        let mid = f64::midpoint(x0, x1);
        let mut covered: Vec<[f64; 2]> = holes
            .iter()
            .filter(|h| h.x[0] < mid && mid < h.x[1])
            .map(|h| [h.y[0].clamp(0.0, height), h.y[1].clamp(0.0, height)])
            .collect();
        covered.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let mut y = 0.0;
        for [b, t] in covered {
            if b > y {
                geometry.add_box([x0, y, z[0]], [x1, b, z[1]], &identity);
            }
            y = f64::max(y, t);
        }
        if height > y {
            geometry.add_box([x0, y, z[0]], [x1, height, z[1]], &identity);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_facing_up(g: &Geometry) -> f64 {
        let mut total = 0.0;
        for t in g.indices.chunks_exact(3) {
            let p = |i: u32| {
                let v = g.positions[i as usize];
                Vector3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
            };
            let n = (p(t[1]) - p(t[0])).cross(&(p(t[2]) - p(t[0])));
            total += n.y / 2.0;
        }
        total
    }

    #[test]
    fn a_floor_faces_up_and_a_ceiling_down_whatever_the_outline_order() {
        let square = [[0.0, 0.0], [0.0, 2.0], [3.0, 2.0], [3.0, 0.0]];
        let reversed: Vec<[f64; 2]> = square.iter().rev().copied().collect();
        for outline in [&square[..], &reversed[..]] {
            let mut floor = Geometry::default();
            assert!(floor.add_polygon(outline, 0.0, true));
            assert!((area_facing_up(&floor) - 6.0).abs() < 1e-9);
            let mut ceiling = Geometry::default();
            assert!(ceiling.add_polygon(outline, 2.5, false));
            assert!((area_facing_up(&ceiling) + 6.0).abs() < 1e-9);
        }
    }

    #[test]
    fn a_box_is_closed_and_its_faces_point_outwards() {
        let mut g = Geometry::default();
        g.add_box([-1.0, 0.0, -0.5], [1.0, 2.0, 0.5], &Isometry3::identity());
        assert_eq!(g.positions.len(), 24);
        assert_eq!(g.indices.len(), 36);
        // Each face's winding agrees with its normal.
        for t in g.indices.chunks_exact(3) {
            let p = |i: u32| {
                let v = g.positions[i as usize];
                Vector3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
            };
            let n = g.normals[t[0] as usize];
            let face = (p(t[1]) - p(t[0])).cross(&(p(t[2]) - p(t[0])));
            let dot = face.dot(&Vector3::new(f64::from(n[0]), f64::from(n[1]), f64::from(n[2])));
            assert!(dot > 0.0);
        }
        assert_eq!(g.bounds(), Some(([-1.0, 0.0, -0.5], [1.0, 2.0, 0.5])));
    }

    #[test]
    fn a_wall_slab_leaves_its_door_open() {
        let mut g = Geometry::default();
        let door = Hole { x: [1.0, 2.0], y: [0.0, 2.0] };
        add_wall_slab(&mut g, 4.0, 2.5, [0.0, 0.1], &[door]);
        // Left column, the lintel over the door, right column.
        assert_eq!(g.positions.len(), 3 * 24);
        // Nothing inside the opening.
        for t in g.indices.chunks_exact(3) {
            let c: Vec<[f32; 3]> = t.iter().map(|&i| g.positions[i as usize]).collect();
            let cx = (c[0][0] + c[1][0] + c[2][0]) / 3.0;
            let cy = (c[0][1] + c[1][1] + c[2][1]) / 3.0;
            assert!(!(cx > 1.0 && cx < 2.0 && cy < 2.0), "a face in the doorway");
        }
    }
}
