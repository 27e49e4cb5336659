//! Temporary narrow phase until the kernel lands (replaced on merge).
use super::{Polygon, P2, TOUCH_EPS};

fn seg_dist(p: P2, a: P2, b: P2) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared().max(1e-300)).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

fn inside(p: P2, poly: &Polygon) -> bool {
    let mut c = false;
    for (a, b) in poly.edges() {
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                c = !c;
            }
        }
    }
    c
}

fn boundary_dist(p: P2, poly: &Polygon) -> f64 {
    poly.edges()
        .map(|(a, b)| seg_dist(p, a, b))
        .fold(f64::INFINITY, f64::min)
}

pub fn overlap(a: &Polygon, b: &Polygon) -> Option<f64> {
    if !a.aabb().meets(b.aabb(), 0.0) {
        return None;
    }
    let mut d: f64 = 0.0;
    for p in a.points() {
        if inside(*p, b) {
            d = d.max(boundary_dist(*p, b));
        }
    }
    for p in b.points() {
        if inside(*p, a) {
            d = d.max(boundary_dist(*p, a));
        }
    }
    (d > TOUCH_EPS).then_some(d)
}

pub fn distance(a: &Polygon, b: &Polygon) -> f64 {
    if overlap(a, b).is_some() {
        return 0.0;
    }
    let mut d = f64::INFINITY;
    for p in a.points() {
        d = d.min(boundary_dist(*p, b));
    }
    for p in b.points() {
        d = d.min(boundary_dist(*p, a));
    }
    d
}
