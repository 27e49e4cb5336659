//! The distance and the contact between two triangle meshes by one walk of the pair of their
//! trees.
//!
//! parry answers a mesh–mesh distance by walking the first mesh's tree against the second
//! mesh's whole box, and for every triangle that walk reaches, a full branch-and-bound walk of
//! the second mesh: a triangle of the first mesh is pruned only when it is farther from the
//! *whole* second mesh's box than the closest pair found, so two meshes whose boxes overlap (a
//! turret and a chuck, a tool's holder and the jaws it passes) walk the second tree once per
//! triangle of the first (2.6 M instructions a query on `crash_live_drill_into_jaws.nc`).
//!
//! Here each mesh has a tree of boxes of its own ([`Tree`], built once, on the first query), and
//! one best-first walk goes down both at once: a pair of nodes is opened only while the distance
//! between their boxes (the second's posed into the first's frame: the box holding its rotated
//! box) is below the closest pair of triangles found so far. A pair of triangles is measured as
//! parry measures it inside its own walk (GJK on the two triangles, the second mesh's triangle
//! first, posed by the inverse of the first's pose of the second), so the answer is parry's:
//! the least of the same triangle distances over the pairs either walk reaches (both prune only
//! pairs whose boxes are at least the best found apart; a pair whose triangles' shadows on the
//! eleven separating axes lie beyond the best is not measured either, [`beyond_best`], as its
//! distance could not better the best). `tests.rs` holds the oracle test.

use std::sync::OnceLock;

use parry3d_f64::math::{Matrix, Pose, Vector};
use parry3d_f64::query::{Contact, DefaultQueryDispatcher, QueryDispatcher};
use parry3d_f64::shape::{Shape, TriMesh, Triangle};

/// A node of a mesh's tree: its box (centre, half extents; own frame) and either two children
/// (`kids`, `kids + 1`) or one triangle.
#[derive(Clone, Copy, Debug)]
struct Node {
    c: Vector,
    h: Vector,
    kids: u32,
    /// The triangle of a leaf; `u32::MAX` for an inner node.
    tri: u32,
}

/// A binary tree of boxes over a mesh's triangles, one triangle per leaf (root at 0).
#[derive(Debug)]
pub(super) struct Tree {
    nodes: Vec<Node>,
}

/// A mesh's tree, built on the first pair query that needs it.
#[derive(Debug, Default)]
pub(super) struct LazyTree(OnceLock<Tree>);

impl LazyTree {
    pub(super) fn get(&self, mesh: &TriMesh) -> &Tree {
        self.0.get_or_init(|| Tree::new(mesh))
    }
}

impl Tree {
    /// The tree of a mesh's triangles: each inner node splits its triangles in two halves by
    /// their centroids along its box's longest side.
    pub(super) fn new(mesh: &TriMesh) -> Tree {
        let v = mesh.vertices();
        let boxes: Vec<(Vector, Vector)> = mesh
            .indices()
            .iter()
            .map(|t| {
                let (a, b, c) = (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
                (a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut tree = Tree { nodes: Vec::new() };
        if order.is_empty() {
            return tree;
        }
        tree.nodes.push(Node {
            c: Vector::ZERO,
            h: Vector::ZERO,
            kids: 0,
            tri: u32::MAX,
        });
        tree.fill(0, &mut order, &boxes);
        tree
    }

    fn fill(&mut self, at: usize, tris: &mut [u32], boxes: &[(Vector, Vector)]) {
        let (mut lo, mut hi) = (Vector::splat(f64::INFINITY), Vector::splat(f64::NEG_INFINITY));
        for &t in tris.iter() {
            lo = lo.min(boxes[t as usize].0);
            hi = hi.max(boxes[t as usize].1);
        }
        self.nodes[at].c = (lo + hi) * 0.5;
        self.nodes[at].h = (hi - lo) * 0.5;
        if tris.len() == 1 {
            self.nodes[at].tri = tris[0];
            return;
        }
        let ext = hi - lo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let key = |t: &u32| {
            let (a, b) = boxes[*t as usize];
            a[axis] + b[axis]
        };
        let mid = tris.len() / 2;
        tris.select_nth_unstable_by(mid, |p, q| key(p).total_cmp(&key(q)));
        let kids = self.nodes.len();
        let blank = self.nodes[at];
        self.nodes.push(blank);
        self.nodes.push(blank);
        self.nodes[at].kids = kids as u32;
        let (left, right) = tris.split_at_mut(mid);
        self.fill(kids, left, boxes);
        self.fill(kids + 1, right, boxes);
    }
}

/// The share [`super::distance`] may come out short of the exact distance beyond the range
/// it measures exactly (the near-miss clearances are below it).
pub(super) const SLACK: f64 = 1.0 / 32.0;

/// The share [`super::distance_bound`] may come out short of the exact distance, at any
/// distance: the advancement's bound. Its steps are then at most half as long, and the walk
/// behind each far cheaper: it leaves closed a pair of boxes within half of the best found,
/// not within a 32nd (measured on the NL1500Y sample; docs/turn-mill.md).
pub(super) const ADVANCE_SLACK: f64 = 1.0 / 2.0;

/// `b`'s posing in `a`'s frame, for boxes: the rotation, its entries' absolute values and the
/// translation.
struct Frame {
    r: Matrix,
    abs: Matrix,
    t: Vector,
}

impl Frame {
    fn new(pos12: &Pose) -> Frame {
        let r = Matrix::from_quat(pos12.rotation);
        let abs = Matrix::from_cols(r.x_axis.abs(), r.y_axis.abs(), r.z_axis.abs());
        Frame {
            r,
            abs,
            t: pos12.translation,
        }
    }

    /// The distance between `a`'s box and the box holding `b`'s box posed in `a`'s frame: a
    /// lower bound of the distance between anything the two boxes hold.
    fn gap(&self, a: &Node, b: &Node) -> f64 {
        let (c, h) = (self.r * b.c + self.t, self.abs * b.h);
        let g = ((c - a.c).abs() - a.h - h).max(Vector::ZERO);
        g.length()
    }
}

/// The signed gap between the shadows of two triangles (one frame) on the axis `n`: positive
/// apart, negative by how much they overlap. `None` when `n` is no longer than `min_len`.
fn shadow_gap(n: Vector, a: &[Vector; 3], b: &[Vector; 3], min_len: f64) -> Option<f64> {
    let len = n.length();
    if !super::positive(len - min_len) {
        return None;
    }
    let (pa, pb) = (a.map(|p| n.dot(p)), b.map(|p| n.dot(p)));
    let (a0, a1) = (pa[0].min(pa[1]).min(pa[2]), pa[0].max(pa[1]).max(pa[2]));
    let (b0, b1) = (pb[0].min(pb[1]).min(pb[2]), pb[0].max(pb[1]).max(pb[2]));
    Some((b0 - a1).max(a0 - b1) / len)
}

/// A lower bound of the distance between two triangles (one frame): the gap between their
/// shadows on the line through their centroids and on each one's normal (0 where they meet).
fn triangle_gap(a: &[Vector; 3], b: &[Vector; 3]) -> f64 {
    let shadow_gap = |n: Vector| shadow_gap(n, a, b, 0.0).map_or(0.0, |g| g.max(0.0));
    let centre = |t: &[Vector; 3]| (t[0] + t[1] + t[2]) / 3.0;
    let normal = |t: &[Vector; 3]| (t[1] - t[0]).cross(t[2] - t[0]);
    shadow_gap(centre(b) - centre(a))
        .max(shadow_gap(normal(a)))
        .max(shadow_gap(normal(b)))
}

/// The distance between the boundaries of two meshes, `b` posed at `pos12` in `a`'s frame,
/// exact below `exact_below` and beyond it a lower bound at least `1 − slack` of it; exact: the
/// least distance of a pair of triangles, measured as parry measures it (see the module docs).
/// `f64::MAX` when no pair of triangles has one.
///
/// Why the slack is sound: a pair of boxes is left closed only when its gap is at least
/// `exact_below` and at least `1 − slack` of the best found then (no less than the best at the
/// end); the answer is the least of the best and the closed gaps, a lower bound of every
/// pair's distance (each pair's is at least its boxes' gap, or its triangles' shadows' gap on
/// an axis, [`triangle_gap`]), and it is a closed gap only when
/// that is at least `exact_below` and at least `1 − slack` of the best, so of the exact one.
/// `slack` is below 1 ([`SLACK`], [`ADVANCE_SLACK`]).
pub(super) fn mesh_distance(
    a: (&TriMesh, &Tree),
    b: (&TriMesh, &Tree),
    pos12: &Pose,
    exact_below: f64,
    slack: f64,
) -> f64 {
    let (ta, tb) = (&a.1.nodes, &b.1.nodes);
    if ta.is_empty() || tb.is_empty() {
        return f64::MAX;
    }
    let frame = Frame::new(pos12);
    let pos21 = pos12.inverse();
    let mut best = f64::MAX;
    // The least gap of the pairs of boxes left closed by the slack.
    let mut closed = f64::INFINITY;
    let mut stack: Vec<(u32, u32, f64)> = Vec::with_capacity(64);
    stack.push((0, 0, frame.gap(&ta[0], &tb[0])));
    // Whether a pair whose distance is at least `gap` is left: it holds no better pair than the
    // best found, or it is far and within the slack of it (its gap then kept as a bound).
    let left = |gap: f64, best: f64, closed: &mut f64| {
        if gap >= best {
            return true;
        }
        let far = gap >= exact_below && gap >= best * (1.0 - slack);
        if far {
            *closed = closed.min(gap);
        }
        far
    };
    while let Some((i, j, gap)) = stack.pop() {
        if left(gap, best, &mut closed) {
            continue;
        }
        let (na, nb) = (&ta[i as usize], &tb[j as usize]);
        let (leaf_a, leaf_b) = (na.tri != u32::MAX, nb.tri != u32::MAX);
        if leaf_a && leaf_b {
            let (tra, trb) = (a.0.triangle(na.tri), b.0.triangle(nb.tri));
            // The triangles' own gap along three axes, at a fraction of GJK's cost.
            let posed = [trb.a, trb.b, trb.c].map(|p| frame.r * p + frame.t);
            let own = [tra.a, tra.b, tra.c];
            if left(triangle_gap(&own, &posed), best, &mut closed) {
                continue;
            }
            if beyond_best(&own, &posed, best) {
                continue;
            }
            if let Ok(d) = DefaultQueryDispatcher.distance(&pos21, &trb, &tra) {
                if d.distance < best {
                    best = d.distance;
                }
            }
            continue;
        }
        // Open the larger box (a leaf cannot be opened).
        let open_a = !leaf_a && (leaf_b || na.h.length_squared() >= nb.h.length_squared());
        let pairs = if open_a {
            [(na.kids, j), (na.kids + 1, j)]
        } else {
            [(i, nb.kids), (i, nb.kids + 1)]
        };
        let gaps = pairs.map(|(p, q)| frame.gap(&ta[p as usize], &tb[q as usize]));
        // The nearer pair is walked first (pushed last).
        let (near, far) = if gaps[0] <= gaps[1] { (0, 1) } else { (1, 0) };
        stack.push((pairs[far].0, pairs[far].1, gaps[far]));
        stack.push((pairs[near].0, pairs[near].1, gaps[near]));
    }
    best.min(closed)
}

/// Whether two triangles (one frame) lie further apart than `best` by more than rounding, by the
/// widest gap of their shadows on the eleven axes that separate two triangles when anything does
/// ([`crossing_bound_below`]): a lower bound of their distance, dearer than [`triangle_gap`]'s
/// three axes and far cheaper than GJK. GJK's distance is that of two points of the triangles
/// (an upper bound of theirs, to rounding), so it would come out at least `best` and leave the
/// walk's answer as it is: skipping it changes nothing, bit for bit. The margin, 1e-9 mm and a
/// billionth of `best`, is far above the roundings of either measure. (On the NL1500Y sample,
/// 132k of the 311k GJK runs of the advancement's distances.)
pub(super) fn beyond_best(a: &[Vector; 3], b: &[Vector; 3], best: f64) -> bool {
    if best == f64::MAX {
        return false;
    }
    let below = -(best + 1e-9 * (1.0 + best));
    crossing_bound_below(a, b, below) < below
}

/// An upper bound of how deep two triangles (one frame) cross: the least overlap of their
/// shadows on the axes that separate two triangles when anything does (each one's normal and
/// the nine crosses of an edge of one with an edge of the other): moving one triangle along
/// such an axis by its overlap leaves the shadows apart, so the triangles too. (It is their
/// penetration depth when those axes are all there: the faces of the Minkowski difference of
/// two triangles are normal to them.) Signed: when the shadows are apart on an axis, minus the
/// widest such gap (the triangles are at least that far apart).
#[cfg(test)]
pub(super) fn crossing_bound(a: &[Vector; 3], b: &[Vector; 3]) -> f64 {
    crossing_bound_below(a, b, f64::NEG_INFINITY)
}

/// [`crossing_bound`], or, as soon as an axis shows a bound below `below`, that bound (also below
/// it): whether the bound is below `below` is answered the same, with fewer axes measured.
fn crossing_bound_below(a: &[Vector; 3], b: &[Vector; 3], below: f64) -> f64 {
    // A cross of nearly parallel edges has no direction to trust.
    let min_len = 1e-12 * (1.0 + a[0].length() + b[0].length());
    let overlap = |n: Vector| shadow_gap(n, a, b, min_len).map_or(f64::INFINITY, |g| -g);
    let edges = |t: &[Vector; 3]| [t[1] - t[0], t[2] - t[1], t[0] - t[2]];
    let (ea, eb) = (edges(a), edges(b));
    let mut bound = overlap(ea[0].cross(ea[1])).min(overlap(eb[0].cross(eb[1])));
    for x in ea {
        for y in eb {
            if bound < below {
                return bound;
            }
            bound = bound.min(overlap(x.cross(y)));
        }
    }
    bound
}

thread_local! {
    /// The EPA of this thread's triangle contacts, kept between them for its buffers (every
    /// query starts by clearing them).
    static EPA: std::cell::RefCell<parry3d_f64::query::epa::EPA> = Default::default();
}

/// parry's contact between two triangles at prediction 0 (`b` posed at `pos12` in `a`'s frame)
/// as its query dispatcher answers it: GJK from the direction between the frames, and EPA when
/// the triangles cross. The same steps on the same numbers, so the same contact; only the EPA's
/// buffers are kept from one query to the next, where the dispatcher allocates them afresh for
/// every pair that crosses.
fn triangle_contact(pos12: &Pose, a: &Triangle, b: &Triangle) -> Option<Contact> {
    use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
    let dir = pos12.translation.try_normalize().unwrap_or(Vector::X);
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(pos12, a, b, dir));
    let found = match gjk::closest_points(pos12, a, b, 0.0, true, &mut simplex) {
        GJKResult::Intersection => EPA.with_borrow_mut(|epa| epa.closest_points(pos12, a, b, &simplex)),
        GJKResult::ClosestPoints(p1, p2, n) => Some((p1, p2, n)),
        _ => None,
    };
    let (point1, point2_1, normal1) = found?;
    let dist = (point2_1 - point1).dot(normal1);
    let point2 = pos12.inverse_transform_point(point2_1);
    let normal2 = pos12.rotation.inverse() * -normal1;
    Some(Contact::new(point1, point2, normal1, normal2, dist))
}

/// EPA's depths are trusted to within this (mm) when a pair of triangles is left out for being
/// unable to go deeper than a depth that matters.
const DEPTH_MARGIN: f64 = 1e-6;

/// What a crossing query must find.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Ask {
    /// parry's contact: the deepest pair, or whether any touches.
    Deepest,
    /// Whether a pair crosses deeper than `eps`, and the deepest one when it is deeper than
    /// `floor` (∞: whether only).
    Over { eps: f64, floor: f64 },
    /// Whether a pair crosses deeper than `eps`, and if none does, whether any touches.
    Touch { eps: f64 },
}

/// The deepest contact between the boundaries of two meshes, `a` posed at `pa` and `b` at `pb`
/// (world frame), as `ask` needs it. [`Ask::Deepest`]: parry's `contact` of the two meshes at
/// prediction 0, the contact of least distance (≤ 0) over the pairs of triangles parry's trees
/// pair (of equal ones the first in their order), each measured as parry measures it. Only the
/// measuring is saved: the pairs are taken deepest-bound first, and a pair whose boxes (in
/// `b`'s frame) overlap along some axis by less than a depth, or whose triangles' shadows do
/// on an axis that can separate them ([`crossing_bound`]), less a margin, cannot cross deeper
/// than it (moving one triangle that far along that axis separates them): with a
/// contact found, the pairs that cannot beat it are not measured; nor, whatever is asked, a pair
/// whose triangles' shadows are apart on one of those axes by more than the margin (parry finds
/// no contact there at prediction 0). [`Ask::Over`]: a contact
/// deeper than `eps` when there is one, the deepest when it is deeper than `floor`; the pairs
/// that can neither beat the floor or the deepest found nor (while none is found) reach `eps`
/// are not measured. [`Ask::Touch`]: a contact deeper than `eps` when there is one, else a
/// contact when there is one; measuring stops at the first that decides.
pub(super) fn mesh_contact(a: &TriMesh, b: &TriMesh, pa: &Pose, pb: &Pose, ask: Ask) -> Option<Contact> {
    let pos12 = pa.inv_mul(pb);
    let pos21 = pos12.inverse();
    let b_box = b.compute_aabb(&pos12);
    // The pairs in parry's order, with the least overlap of their boxes along an axis.
    let mut pairs: Vec<(f64, u32, u32)> = Vec::new();
    for i in a.bvh().intersect_aabb(&b_box) {
        let bi = a.triangle(i).compute_aabb(&pos21);
        for j in b.bvh().intersect_aabb(&bi) {
            let Some(bj) = b.bvh().leaf_node(j).map(|n| n.aabb()) else {
                continue;
            };
            let over = (bi.maxs - bj.mins).min(bj.maxs - bi.mins);
            pairs.push((over.x.min(over.y).min(over.z), i, j));
        }
    }
    // Deepest bound first; among equal bounds, parry's order (the sort is stable).
    let mut order: Vec<u32> = (0..pairs.len() as u32).collect();
    order.sort_by(|&p, &q| pairs[q as usize].0.total_cmp(&pairs[p as usize].0));
    let mut best: Option<(Contact, u32)> = None;
    for k in order {
        let (over, i, j) = pairs[k as usize];
        let deepest = best.as_ref().map_or(f64::NEG_INFINITY, |(c, _)| -c.dist);
        // A pair crossing at most `bound` deep cannot change the answer when `bound` is below
        // this (+∞: nothing can; −∞: anything may).
        let idle_below = match ask {
            Ask::Deepest if best.is_some() => deepest - DEPTH_MARGIN,
            Ask::Deepest => f64::NEG_INFINITY,
            Ask::Over { eps, floor } if deepest > eps => deepest.max(floor) - DEPTH_MARGIN,
            Ask::Over { eps, floor } => (deepest.max(floor) - DEPTH_MARGIN).min(eps - DEPTH_MARGIN),
            Ask::Touch { eps } if deepest > eps => f64::INFINITY,
            Ask::Touch { eps } if best.is_some() => eps - DEPTH_MARGIN,
            Ask::Touch { .. } => f64::NEG_INFINITY,
        };
        // No pair left can (their boxes' bounds are no larger).
        if over < idle_below {
            break;
        }
        let (tri_a, tri_b) = (a.triangle(i), b.triangle(j));
        let va = [tri_a.a, tri_a.b, tri_a.c].map(|p| pos21 * p);
        // Triangles apart by more than the margin have no contact at prediction 0 (GJK finds
        // them apart): whatever is asked, measuring them changes nothing.
        let skip_below = idle_below.max(-DEPTH_MARGIN);
        if over.min(crossing_bound_below(&va, &[tri_b.a, tri_b.b, tri_b.c], skip_below)) < skip_below {
            continue;
        }
        let Some(c) = triangle_contact(&pos21, &tri_b, &tri_a) else {
            continue;
        };
        let better = match &best {
            None => !c.dist.is_nan(),
            Some((b, at)) => c.dist < b.dist || (c.dist == b.dist && k < *at),
        };
        if better {
            best = Some((c.flipped(), k));
        }
    }
    best.map(|(mut c, _)| {
        c.transform_by_mut(pa, pb);
        c
    })
}
