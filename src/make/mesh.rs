//! The shapes a made asset is built of, and the triangle mesh they become.
//!
//! A generator adds [`Shape`]s to a [`Build`], each on a named part with a swatch (its colour and
//! finish). Coordinates are metres in the asset's own frame while it is built: `x` to its
//! right, `y` up from its bottom, `z` to its front (AI2-THOR's front: a rotation of 0 faces
//! `+z`). [`Build::finish`] turns the shapes into one mesh centred on its bounding box, as the
//! run-time asset format wants: one vertex per face corner (flat shading), counter-clockwise
//! triangles seen from outside, and one convex collider per shape (its box).

use std::f64::consts::TAU;

/// An axis of the asset's frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Left to right.
    X,
    /// Up.
    Y,
    /// Back to front.
    Z,
}

/// One solid of a part.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// The box `min..max`.
    Cuboid {
        /// Its lowest corner.
        min: [f64; 3],
        /// Its highest corner.
        max: [f64; 3],
    },
    /// A round solid along `axis`: radius `r0` at `from`, `r1` at `from + length` (a cylinder
    /// when they are equal, a cone or frustum otherwise), with an inner radius for a tube
    /// (`inner > 0`: a ring with walls, open at both ends).
    Round {
        /// Its axis.
        axis: Axis,
        /// The centre of its start face.
        from: [f64; 3],
        /// Its length along the axis.
        length: f64,
        /// Radius at the start.
        r0: f64,
        /// Radius at the end.
        r1: f64,
        /// Inner radius as a share of the outer one (0: solid).
        inner: f64,
        /// Segments round the axis.
        segments: usize,
    },
    /// A vertical sheet whose plan is the polyline `path` (points `[x, z]`), `thickness` thick,
    /// from height `y0` to `y1`: a pleated curtain, a folded screen.
    Sheet {
        /// The middle line of the sheet, in plan.
        path: Vec<[f64; 2]>,
        /// Its thickness, metres.
        thickness: f64,
        /// Its bottom height.
        y0: f64,
        /// Its top height.
        y1: f64,
    },
}

impl Shape {
    /// A box from its lowest corner and its size.
    pub fn cuboid(min: [f64; 3], size: [f64; 3]) -> Shape {
        Shape::Cuboid { min, max: [min[0] + size[0], min[1] + size[1], min[2] + size[2]] }
    }

    /// A box centred on `centre` in `x` and `z`, standing on `y`.
    pub fn block(centre_x: f64, y: f64, centre_z: f64, size: [f64; 3]) -> Shape {
        Shape::cuboid([centre_x - size[0] / 2.0, y, centre_z - size[2] / 2.0], size)
    }

    /// A cylinder along `axis` from `from`.
    pub fn cylinder(axis: Axis, from: [f64; 3], length: f64, radius: f64) -> Shape {
        Shape::Round { axis, from, length, r0: radius, r1: radius, inner: 0.0, segments: 16 }
    }

    /// A cone or frustum along `axis` from `from`.
    pub fn frustum(axis: Axis, from: [f64; 3], length: f64, r0: f64, r1: f64) -> Shape {
        Shape::Round { axis, from, length, r0, r1, inner: 0.0, segments: 16 }
    }

    /// A tube (a ring with walls) along `axis`: outer radius `radius`, inner `inner × radius`.
    pub fn tube(axis: Axis, from: [f64; 3], length: f64, radius: f64, inner: f64) -> Shape {
        Shape::Round { axis, from, length, r0: radius, r1: radius, inner, segments: 20 }
    }

    /// A round solid with `n` segments round its axis (fewer for small details, so that an
    /// asset stays small on disk); other shapes are unchanged.
    #[must_use]
    pub fn with_segments(mut self, n: usize) -> Shape {
        if let Shape::Round { segments, .. } = &mut self {
            *segments = n.max(3);
        }
        self
    }

    /// The box that holds it.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        match self {
            Shape::Cuboid { min, max } => (*min, *max),
            Shape::Round { axis, from, length, r0, r1, .. } => {
                let r = r0.max(*r1);
                let mut min = *from;
                let mut max = *from;
                let along = axis_index(*axis);
                for i in 0..3 {
                    if i == along {
                        max[i] += length;
                    } else {
                        min[i] -= r;
                        max[i] += r;
                    }
                }
                (min, max)
            }
            Shape::Sheet { path, thickness, y0, y1 } => {
                let h = thickness / 2.0;
                let (mut min, mut max) = (
                    [f64::INFINITY, *y0, f64::INFINITY],
                    [f64::NEG_INFINITY, *y1, f64::NEG_INFINITY],
                );
                for p in path {
                    min[0] = min[0].min(p[0] - h);
                    max[0] = max[0].max(p[0] + h);
                    min[2] = min[2].min(p[1] - h);
                    max[2] = max[2].max(p[1] + h);
                }
                (min, max)
            }
        }
    }
}

fn axis_index(axis: Axis) -> usize {
    match axis {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    }
}

/// A named part of a made asset: its swatch and its shapes.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// What it is (`post`, `pane`, `frame`).
    pub name: &'static str,
    /// Index of its swatch in the asset's palette.
    pub swatch: usize,
    /// Its solids.
    pub shapes: Vec<Shape>,
}

/// The parts of a made asset while a generator builds it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Build {
    /// The parts, in the order they were added.
    pub parts: Vec<Part>,
}

impl Build {
    /// Adds shapes to the part `name` with swatch `swatch` (a new part unless the last one has
    /// that name and swatch).
    pub fn add(&mut self, name: &'static str, swatch: usize, shape: Shape) {
        match self.parts.last_mut() {
            Some(last) if last.name == name && last.swatch == swatch => last.shapes.push(shape),
            _ => self.parts.push(Part { name, swatch, shapes: vec![shape] }),
        }
    }

    /// The box that holds every shape, `(min, max)`; a zero box when there is none.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for s in self.parts.iter().flat_map(|p| &p.shapes) {
            let (a, b) = s.bounds();
            for i in 0..3 {
                min[i] = min[i].min(a[i]);
                max[i] = max[i].max(b[i]);
            }
        }
        if min[0].is_finite() {
            (min, max)
        } else {
            ([0.0; 3], [0.0; 3])
        }
    }

    /// The mesh: every shape triangulated, moved so that the bounding box is centred on the
    /// origin, with each vertex's uv at its part's swatch cell (`cell_uv`).
    pub fn finish(&self, cell_uv: impl Fn(usize) -> [f64; 2]) -> Mesh {
        let mut mesh = Mesh::default();
        for (p, part) in self.parts.iter().enumerate() {
            let uv = cell_uv(part.swatch);
            for shape in &part.shapes {
                triangulate(shape, &mut mesh);
                mesh.uvs.resize(mesh.vertices.len(), uv);
                mesh.part_of.resize(mesh.triangles.len() / 3, p);
                mesh.colliders.push(shape.bounds());
            }
        }
        // The box of the vertices themselves (a sheet's ends and a round solid's facets stop
        // inside their shapes' boxes), centred on the origin.
        let (mut min, mut max) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for v in &mesh.vertices {
            for i in 0..3 {
                min[i] = min[i].min(v[i]);
                max[i] = max[i].max(v[i]);
            }
        }
        if mesh.vertices.is_empty() {
            (min, max) = ([0.0; 3], [0.0; 3]);
        }
        let centre = [0, 1, 2].map(|i| f64::midpoint(min[i], max[i]));
        for v in &mut mesh.vertices {
            for i in 0..3 {
                v[i] -= centre[i];
            }
        }
        for (lo, hi) in &mut mesh.colliders {
            for i in 0..3 {
                lo[i] = lo[i].max(min[i]) - centre[i];
                hi[i] = hi[i].min(max[i]) - centre[i];
            }
        }
        mesh.size = [0, 1, 2].map(|i| max[i] - min[i]);
        mesh
    }
}

/// A made asset's triangle mesh, centred on its bounding box.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, metres; one per face corner.
    pub vertices: Vec<[f64; 3]>,
    /// Unit normals, one per vertex.
    pub normals: Vec<[f64; 3]>,
    /// Texture coordinates, one per vertex.
    pub uvs: Vec<[f64; 2]>,
    /// Triangles, three vertex indices each, counter-clockwise seen from outside.
    pub triangles: Vec<u32>,
    /// The part of each triangle (index into the build's parts).
    pub part_of: Vec<usize>,
    /// One convex piece per shape: its box `(min, max)`.
    pub colliders: Vec<([f64; 3], [f64; 3])>,
    /// The size of the bounding box, metres `[x, y, z]`.
    pub size: [f64; 3],
}

impl Mesh {
    fn vertex(&mut self, p: [f64; 3], n: [f64; 3]) -> u32 {
        self.vertices.push(p);
        self.normals.push(normalize(n));
        (self.vertices.len() - 1) as u32
    }

    /// A flat quad `a b c d`, counter-clockwise seen from outside.
    fn quad(&mut self, q: [[f64; 3]; 4]) {
        let n = cross(sub(q[1], q[0]), sub(q[2], q[0]));
        let n = if norm(n) < 1e-12 { cross(sub(q[2], q[0]), sub(q[3], q[0])) } else { n };
        if norm(n) < 1e-12 {
            return;
        }
        let i = q.map(|p| self.vertex(p, n));
        self.triangles.extend([i[0], i[1], i[2], i[0], i[2], i[3]]);
    }

    /// A flat triangle, counter-clockwise seen from outside.
    fn triangle(&mut self, t: [[f64; 3]; 3]) {
        let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
        if norm(n) < 1e-12 {
            return;
        }
        let i = t.map(|p| self.vertex(p, n));
        self.triangles.extend(i);
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    if n < 1e-12 {
        [0.0, 1.0, 0.0]
    } else {
        [a[0] / n, a[1] / n, a[2] / n]
    }
}

/// Appends the triangles of one shape.
fn triangulate(shape: &Shape, mesh: &mut Mesh) {
    match shape {
        Shape::Cuboid { min, max } => cuboid(*min, *max, mesh),
        Shape::Round { axis, from, length, r0, r1, inner, segments } => {
            round(*axis, *from, *length, [*r0, *r1], *inner, (*segments).max(3), mesh);
        }
        Shape::Sheet { path, thickness, y0, y1 } => sheet(path, *thickness, *y0, *y1, mesh),
    }
}

fn cuboid(min: [f64; 3], max: [f64; 3], mesh: &mut Mesh) {
    if (0..3).any(|i| max[i] - min[i] < 1e-5) {
        return;
    }
    let p = |x: usize, y: usize, z: usize| {
        [
            if x == 0 { min[0] } else { max[0] },
            if y == 0 { min[1] } else { max[1] },
            if z == 0 { min[2] } else { max[2] },
        ]
    };
    mesh.quad([p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)]);
    mesh.quad([p(0, 0, 1), p(0, 1, 1), p(0, 1, 0), p(0, 0, 0)]);
    mesh.quad([p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)]);
    mesh.quad([p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)]);
    mesh.quad([p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)]);
    mesh.quad([p(0, 1, 0), p(1, 1, 0), p(1, 0, 0), p(0, 0, 0)]);
}

/// A point at angle `a` and radius `r`, `t` along `axis` from `from`. The two directions
/// round the axis are ordered so that increasing `a` turns counter-clockwise seen from the
/// axis's end.
fn on_circle(axis: Axis, from: [f64; 3], t: f64, r: f64, a: f64) -> [f64; 3] {
    let (c, s) = (r * a.cos(), r * a.sin());
    match axis {
        Axis::X => [from[0] + t, from[1] + c, from[2] + s],
        Axis::Y => [from[0] + s, from[1] + t, from[2] + c],
        Axis::Z => [from[0] + c, from[1] + s, from[2] + t],
    }
}

fn round(
    axis: Axis,
    from: [f64; 3],
    length: f64,
    r: [f64; 2],
    inner: f64,
    segments: usize,
    mesh: &mut Mesh,
) {
    if length < 1e-5 || r[0].max(r[1]) < 1e-5 {
        return;
    }
    let angle = |k: usize| TAU * k as f64 / segments as f64;
    let inner = inner.clamp(0.0, 0.95);
    for k in 0..segments {
        let (a, b) = (angle(k), angle(k + 1));
        // The outer side.
        let q = [
            on_circle(axis, from, 0.0, r[0], a),
            on_circle(axis, from, 0.0, r[0], b),
            on_circle(axis, from, length, r[1], b),
            on_circle(axis, from, length, r[1], a),
        ];
        side(mesh, q, false);
        if inner > 0.0 {
            let (i0, i1) = (r[0] * inner, r[1] * inner);
            let q = [
                on_circle(axis, from, 0.0, i0, a),
                on_circle(axis, from, 0.0, i0, b),
                on_circle(axis, from, length, i1, b),
                on_circle(axis, from, length, i1, a),
            ];
            side(mesh, q, true);
            // The two rims.
            mesh.quad([
                on_circle(axis, from, 0.0, i0, a),
                on_circle(axis, from, 0.0, i0, b),
                on_circle(axis, from, 0.0, r[0], b),
                on_circle(axis, from, 0.0, r[0], a),
            ]);
            let end = [
                on_circle(axis, from, length, r[1], a),
                on_circle(axis, from, length, r[1], b),
                on_circle(axis, from, length, i1, b),
                on_circle(axis, from, length, i1, a),
            ];
            mesh.quad(end);
        } else {
            let c0 = on_circle(axis, from, 0.0, 0.0, 0.0);
            let c1 = on_circle(axis, from, length, 0.0, 0.0);
            if r[0] > 1e-5 {
                mesh.triangle([
                    c0,
                    on_circle(axis, from, 0.0, r[0], b),
                    on_circle(axis, from, 0.0, r[0], a),
                ]);
            }
            if r[1] > 1e-5 {
                mesh.triangle([
                    c1,
                    on_circle(axis, from, length, r[1], a),
                    on_circle(axis, from, length, r[1], b),
                ]);
            }
        }
    }
}

/// One side quad of a round solid with smooth normals pointing away from (or, `inward`,
/// towards) the axis.
fn side(mesh: &mut Mesh, q: [[f64; 3]; 4], inward: bool) {
    let n = cross(sub(q[1], q[0]), sub(q[3], q[0]));
    if norm(n) < 1e-12 {
        return;
    }
    let n = if inward { [-n[0], -n[1], -n[2]] } else { n };
    let i = q.map(|p| mesh.vertex(p, n));
    if inward {
        mesh.triangles.extend([i[0], i[2], i[1], i[0], i[3], i[2]]);
    } else {
        mesh.triangles.extend([i[0], i[1], i[2], i[0], i[2], i[3]]);
    }
}

/// A sheet: the path offset half the thickness to each side, extruded from `y0` to `y1`,
/// closed at its ends, top and bottom.
fn sheet(path: &[[f64; 2]], thickness: f64, y0: f64, y1: f64, mesh: &mut Mesh) {
    if path.len() < 2 || y1 - y0 < 1e-5 || thickness < 1e-5 {
        return;
    }
    let h = thickness / 2.0;
    // The normal of the path at each point (average of its segments').
    let seg_normal = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
        let l = (dx * dx + dz * dz).sqrt().max(1e-12);
        [dz / l, -dx / l]
    };
    let n = path.len();
    let normals: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a =
                if i > 0 { seg_normal(path[i - 1], path[i]) } else { seg_normal(path[0], path[1]) };
            let b = if i + 1 < n { seg_normal(path[i], path[i + 1]) } else { a };
            let m = [a[0] + b[0], a[1] + b[1]];
            let l = (m[0] * m[0] + m[1] * m[1]).sqrt().max(1e-12);
            [m[0] / l, m[1] / l]
        })
        .collect();
    let left: Vec<[f64; 2]> =
        path.iter().zip(&normals).map(|(p, m)| [p[0] + m[0] * h, p[1] + m[1] * h]).collect();
    let right: Vec<[f64; 2]> =
        path.iter().zip(&normals).map(|(p, m)| [p[0] - m[0] * h, p[1] - m[1] * h]).collect();
    let at = |p: [f64; 2], y: f64| [p[0], y, p[1]];
    for i in 0..n - 1 {
        // Both faces and the top and bottom strips of segment i.
        mesh.quad([at(left[i], y0), at(left[i], y1), at(left[i + 1], y1), at(left[i + 1], y0)]);
        mesh.quad([at(right[i + 1], y0), at(right[i + 1], y1), at(right[i], y1), at(right[i], y0)]);
        mesh.quad([at(left[i], y1), at(right[i], y1), at(right[i + 1], y1), at(left[i + 1], y1)]);
        mesh.quad([at(left[i + 1], y0), at(right[i + 1], y0), at(right[i], y0), at(left[i], y0)]);
    }
    mesh.quad([at(right[0], y0), at(right[0], y1), at(left[0], y1), at(left[0], y0)]);
    mesh.quad([
        at(left[n - 1], y0),
        at(left[n - 1], y1),
        at(right[n - 1], y1),
        at(right[n - 1], y0),
    ]);
}

/// A rectangular frame of bars `bar` wide in the plane `z0..z1`, round the opening
/// `x0..x1 × y0..y1` (its outer edge).
pub fn frame(
    b: &mut Build,
    name: &'static str,
    swatch: usize,
    [x0, x1]: [f64; 2],
    [y0, y1]: [f64; 2],
    [z0, z1]: [f64; 2],
    bar: f64,
) {
    let bar = bar.min((x1 - x0) / 3.0).min((y1 - y0) / 3.0);
    b.add(name, swatch, Shape::Cuboid { min: [x0, y0, z0], max: [x0 + bar, y1, z1] });
    b.add(name, swatch, Shape::Cuboid { min: [x1 - bar, y0, z0], max: [x1, y1, z1] });
    b.add(name, swatch, Shape::Cuboid { min: [x0 + bar, y0, z0], max: [x1 - bar, y0 + bar, z1] });
    b.add(name, swatch, Shape::Cuboid { min: [x0 + bar, y1 - bar, z0], max: [x1 - bar, y1, z1] });
}

/// A flat frame (a rug's border) of bands `band` wide round the rectangle `x0..x1 × z0..z1`,
/// from height `y0` to `y1`.
pub fn frame_flat(
    b: &mut Build,
    name: &'static str,
    swatch: usize,
    [x0, x1]: [f64; 2],
    [z0, z1]: [f64; 2],
    [y0, y1]: [f64; 2],
    band: f64,
) {
    let band = band.min((x1 - x0) / 3.0).min((z1 - z0) / 3.0);
    b.add(name, swatch, Shape::Cuboid { min: [x0, y0, z0], max: [x1, y1, z0 + band] });
    b.add(name, swatch, Shape::Cuboid { min: [x0, y0, z1 - band], max: [x1, y1, z1] });
    b.add(
        name,
        swatch,
        Shape::Cuboid { min: [x0, y0, z0 + band], max: [x0 + band, y1, z1 - band] },
    );
    b.add(
        name,
        swatch,
        Shape::Cuboid { min: [x1 - band, y0, z0 + band], max: [x1, y1, z1 - band] },
    );
}

/// An open box (a tray, a carcass seen from the front) of walls `wall` thick filling
/// `min..max`: the bottom and four sides, no top.
pub fn tray(
    b: &mut Build,
    name: &'static str,
    swatch: usize,
    min: [f64; 3],
    max: [f64; 3],
    wall: f64,
) {
    let w = wall.min((max[0] - min[0]) / 4.0).min((max[2] - min[2]) / 4.0).min(max[1] - min[1]);
    b.add(name, swatch, Shape::Cuboid { min, max: [max[0], min[1] + w, max[2]] });
    b.add(
        name,
        swatch,
        Shape::Cuboid { min: [min[0], min[1] + w, min[2]], max: [min[0] + w, max[1], max[2]] },
    );
    b.add(
        name,
        swatch,
        Shape::Cuboid { min: [max[0] - w, min[1] + w, min[2]], max: [max[0], max[1], max[2]] },
    );
    b.add(
        name,
        swatch,
        Shape::Cuboid {
            min: [min[0] + w, min[1] + w, min[2]],
            max: [max[0] - w, max[1], min[2] + w],
        },
    );
    b.add(
        name,
        swatch,
        Shape::Cuboid {
            min: [min[0] + w, min[1] + w, max[2] - w],
            max: [max[0] - w, max[1], max[2]],
        },
    );
}

/// A pleated path along `x` from `x0` to `x1` at depth `z`, folds `depth` deep every `pitch`.
pub fn pleats(x0: f64, x1: f64, z: f64, depth: f64, pitch: f64) -> Vec<[f64; 2]> {
    let n = (((x1 - x0) / pitch).round() as usize).clamp(2, 64) * 2;
    (0..=n)
        .map(|i| {
            let x = x0 + (x1 - x0) * i as f64 / n as f64;
            let dz = if i % 2 == 0 { 0.0 } else { depth };
            [x, z + dz]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle's winding agrees with its vertices' normals (counter-clockwise seen from
    /// where the normal points).
    fn windings_agree(mesh: &Mesh) -> bool {
        mesh.triangles.chunks_exact(3).all(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.vertices[i as usize]);
            let n = cross(sub(b, a), sub(c, a));
            let vn = mesh.normals[t[0] as usize];
            n[0] * vn[0] + n[1] * vn[1] + n[2] * vn[2] > -1e-12
        })
    }

    #[test]
    fn a_box_is_twelve_outward_triangles_centred_on_its_bounds() {
        let mut b = Build::default();
        b.add("board", 0, Shape::cuboid([0.0, 0.0, 0.0], [1.0, 0.5, 0.2]));
        let mesh = b.finish(|_| [0.5, 0.5]);
        assert_eq!(mesh.triangles.len(), 36);
        assert_eq!(mesh.vertices.len(), 24);
        assert!(windings_agree(&mesh));
        assert_eq!(mesh.size, [1.0, 0.5, 0.2]);
        let ys: Vec<f64> = mesh.vertices.iter().map(|v| v[1]).collect();
        assert!(ys.iter().all(|y| (y.abs() - 0.25).abs() < 1e-12));
    }

    #[test]
    fn round_solids_and_sheets_wind_outwards() {
        let mut b = Build::default();
        b.add("post", 0, Shape::cylinder(Axis::Y, [0.0, 0.0, 0.0], 1.0, 0.05));
        b.add("pane", 1, Shape::cylinder(Axis::Z, [0.0, 1.0, 0.0], 0.02, 0.3));
        b.add("rim", 1, Shape::tube(Axis::Y, [0.0, 0.0, 0.0], 0.1, 0.3, 0.8));
        b.add("spout", 1, Shape::frustum(Axis::X, [0.0, 0.5, 0.0], 0.2, 0.05, 0.0));
        b.add(
            "pleats",
            2,
            Shape::Sheet {
                path: vec![[0.0, 0.0], [0.1, 0.05], [0.2, 0.0]],
                thickness: 0.01,
                y0: 0.0,
                y1: 2.0,
            },
        );
        let mesh = b.finish(|s| [s as f64 / 4.0, 0.5]);
        assert!(windings_agree(&mesh));
        assert_eq!(mesh.normals.len(), mesh.vertices.len());
        assert_eq!(mesh.uvs.len(), mesh.vertices.len());
        assert_eq!(mesh.part_of.len() * 3, mesh.triangles.len());
        assert_eq!(mesh.colliders.len(), 5);
        assert!(mesh.triangles.iter().all(|&i| (i as usize) < mesh.vertices.len()));
    }
}
