//! A bounding volume hierarchy over a triangle mesh, for the mesh scene's ray casts: the
//! G-buffer's closest hits and the occlusion rays' any-hit tests. Built once by median
//! splits along the longest axis of the triangles' centroids (leaves of at most
//! [`LEAF`] triangles); traversed with a stack, nearer child first.

/// A 3-vector.
pub type V3 = [f32; 3];

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn dot(a: V3, b: V3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(crate) fn normalize(a: V3) -> V3 {
    let l = dot(a, a).sqrt();
    if l > 0.0 {
        a.map(|x| x / l)
    } else {
        [0.0, 1.0, 0.0]
    }
}
pub(crate) fn along(o: V3, d: V3, t: f32) -> V3 {
    [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]]
}

/// Triangles per leaf at most.
pub const LEAF: usize = 4;

/// A node: its box, and either two children (`count == 0`, the left one at `first`, the
/// right one at `first + 1`) or `count` triangles from `first` of the ordered list.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: V3,
    hi: V3,
    first: u32,
    count: u32,
}

/// A ray's closest hit: its parameter, the triangle, and the barycentrics of vertices 1
/// and 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter.
    pub t: f32,
    /// Triangle index (into the mesh's triangles).
    pub triangle: u32,
    /// Barycentric weights of the triangle's second and third vertex.
    pub uv: [f32; 2],
}

/// The hierarchy over a mesh's triangles (it keeps their corners).
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Triangle indices in leaf order.
    order: Vec<u32>,
    /// Each triangle's corners.
    corners: Vec<[V3; 3]>,
}

impl Bvh {
    /// The hierarchy of the triangles `triangles` over `positions` (a corner index out of
    /// range reads the origin).
    #[must_use]
    pub fn new(positions: &[V3], triangles: &[[u32; 3]]) -> Self {
        let at = |i: u32| positions.get(i as usize).copied().unwrap_or_default();
        let corners: Vec<[V3; 3]> = triangles.iter().map(|t| t.map(at)).collect();
        let centroids: Vec<V3> = corners
            .iter()
            .map(|c| core::array::from_fn(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0))
            .collect();
        let mut b = Self {
            nodes: vec![Node {
                lo: [0.0; 3],
                hi: [0.0; 3],
                first: 0,
                count: 0,
            }],
            order: (0..corners.len() as u32).collect(),
            corners,
        };
        b.split(0, 0, b.order.len(), &centroids);
        b
    }

    /// Makes node `node` hold the triangles `order[start..end]`, splitting it while it
    /// holds more than [`LEAF`].
    fn split(&mut self, node: usize, start: usize, end: usize, centroids: &[V3]) {
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        let (mut clo, mut chi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for &t in &self.order[start..end] {
            for p in self.corners[t as usize] {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            let c = centroids[t as usize];
            for k in 0..3 {
                clo[k] = clo[k].min(c[k]);
                chi[k] = chi[k].max(c[k]);
            }
        }
        let extent = sub(chi, clo);
        let axis = (0..3)
            .max_by(|&a, &b| extent[a].total_cmp(&extent[b]))
            .unwrap_or(0);
        self.nodes[node].lo = lo;
        self.nodes[node].hi = hi;
        if end - start <= LEAF || extent[axis] <= 0.0 {
            self.nodes[node].first = start as u32;
            self.nodes[node].count = (end - start) as u32;
            return;
        }
        let mid = start + (end - start) / 2;
        self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
            centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
        });
        let left = self.nodes.len();
        let empty = self.nodes[node];
        self.nodes.extend([empty, empty]);
        self.nodes[node].first = left as u32;
        self.split(left, start, mid, centroids);
        self.split(left + 1, mid, end, centroids);
    }

    /// The entry parameter of the ray `o + t d` (`inv` = `1 / d`) into node `n`'s box
    /// within `(0, t_max)`, `None` if it misses.
    fn enter(&self, n: usize, o: V3, inv: V3, t_max: f32) -> Option<f32> {
        let b = &self.nodes[n];
        let (mut near, mut far) = (0.0_f32, t_max);
        for k in 0..3 {
            let a = (b.lo[k] - o[k]) * inv[k];
            let c = (b.hi[k] - o[k]) * inv[k];
            // NaN (0 * inf on a face) leaves the interval as it is.
            near = near.max(a.min(c));
            far = far.min(a.max(c));
        }
        (near <= far).then_some(near)
    }

    /// The closest hit of the ray `o + t d` with `0 < t < t_max`; with `any`, the first
    /// hit found (an occlusion test).
    fn cast(&self, o: V3, d: V3, t_max: f32, any: bool) -> Option<Hit> {
        if self.corners.is_empty() {
            return None;
        }
        let inv = d.map(|x| 1.0 / x);
        let mut best: Option<Hit> = None;
        let mut limit = t_max;
        let mut stack = [0_u32; 64];
        let mut depth = 0;
        if self.enter(0, o, inv, limit).is_some() {
            depth = 1;
        }
        while depth > 0 {
            depth -= 1;
            let n = &self.nodes[stack[depth] as usize];
            if n.count > 0 {
                let leaf = &self.order[n.first as usize..(n.first + n.count) as usize];
                for &t in leaf {
                    if let Some((s, uv)) = triangle(&self.corners[t as usize], o, d, limit) {
                        limit = s;
                        best = Some(Hit {
                            t: s,
                            triangle: t,
                            uv,
                        });
                        if any {
                            return best;
                        }
                    }
                }
                continue;
            }
            let (a, b) = (n.first as usize, n.first as usize + 1);
            let (ea, eb) = (self.enter(a, o, inv, limit), self.enter(b, o, inv, limit));
            // Push the farther child first, so the nearer one is visited first.
            let mut push = |k: usize| {
                if depth < stack.len() {
                    stack[depth] = k as u32;
                    depth += 1;
                }
            };
            match (ea, eb) {
                (Some(x), Some(y)) if x <= y => {
                    push(b);
                    push(a);
                }
                (Some(_), Some(_)) => {
                    push(a);
                    push(b);
                }
                (Some(_), None) => push(a),
                (None, Some(_)) => push(b),
                (None, None) => {}
            }
        }
        best
    }

    /// The closest hit of the ray `o + t d` with `0 < t < t_max`.
    #[must_use]
    pub fn closest(&self, o: V3, d: V3, t_max: f32) -> Option<Hit> {
        self.cast(o, d, t_max, false)
    }

    /// Whether the ray `o + t d` hits a triangle with `0 < t < t_max`.
    #[must_use]
    pub fn occluded(&self, o: V3, d: V3, t_max: f32) -> bool {
        self.cast(o, d, t_max, true).is_some()
    }
}

/// The ray `o + t d` against triangle `c` (Möller-Trumbore, both faces): its parameter
/// in `(0, t_max)` and the barycentrics of corners 1 and 2, `None` if it misses.
#[must_use]
pub fn triangle(c: &[V3; 3], o: V3, d: V3, t_max: f32) -> Option<(f32, [f32; 2])> {
    let (e1, e2) = (sub(c[1], c[0]), sub(c[2], c[0]));
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(o, c[0]);
    let u = dot(s, p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = cross(s, e1);
    let v = dot(d, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = dot(e2, q) * inv;
    (t > 0.0 && t < t_max).then_some((t, [u, v]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic cloud of small triangles.
    fn cloud(n: u32) -> (Vec<V3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        let mut t = Vec::new();
        for i in 0..n {
            let h = spvg::sequence::pcg3d16([i, 17, 3]);
            let c = h.map(|x| x as f32 / 65536.0 * 10.0);
            let k = p.len() as u32;
            p.extend([
                c,
                [c[0] + 0.7, c[1], c[2] + 0.1],
                [c[0], c[1] + 0.6, c[2] - 0.2],
            ]);
            t.push([k, k + 1, k + 2]);
        }
        (p, t)
    }

    /// The hierarchy's closest hit and occlusion equal a brute-force loop over every
    /// triangle (the independent reference), on rays in every direction.
    #[test]
    fn the_hierarchy_finds_what_every_triangle_finds() {
        let (p, tris) = cloud(300);
        let bvh = Bvh::new(&p, &tris);
        let corners: Vec<[V3; 3]> = tris.iter().map(|t| t.map(|i| p[i as usize])).collect();
        let mut hits = 0;
        for i in 0..2000_u32 {
            let h = spvg::sequence::pcg3d16([i, 5, 9]);
            let o = h.map(|x| x as f32 / 65536.0 * 12.0 - 1.0);
            let g = spvg::sequence::pcg3d16([i, 6, 9]);
            let d = normalize(g.map(|x| x as f32 / 32768.0 - 1.0));
            for t_max in [3.0, 1e9] {
                let brute = corners
                    .iter()
                    .enumerate()
                    .filter_map(|(k, c)| triangle(c, o, d, t_max).map(|(t, _)| (t, k as u32)))
                    .min_by(|a, b| a.0.total_cmp(&b.0));
                let got = bvh.closest(o, d, t_max).map(|h| (h.t, h.triangle));
                assert_eq!(got, brute, "ray {i}, t_max {t_max}");
                assert_eq!(bvh.occluded(o, d, t_max), brute.is_some(), "ray {i}");
                hits += usize::from(brute.is_some());
            }
        }
        assert!(hits > 200, "the rays hit something: {hits}");
    }

    #[test]
    fn a_ray_through_a_triangle_hits_it_at_its_barycentrics() {
        let c = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let (t, uv) = triangle(&c, [0.25, 0.5, 2.0], [0.0, 0.0, -1.0], 10.0).expect("a hit");
        assert_eq!((t, uv), (2.0, [0.25, 0.5]));
        assert_eq!(triangle(&c, [0.25, 0.5, 2.0], [0.0, 0.0, -1.0], 1.5), None);
        assert_eq!(triangle(&c, [0.9, 0.9, 2.0], [0.0, 0.0, -1.0], 10.0), None);
        assert!(
            Bvh::new(&[], &[])
                .closest([0.0; 3], [1.0, 0.0, 0.0], 1.0)
                .is_none()
        );
    }
}
