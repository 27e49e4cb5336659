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

/// One contact episode of a sweep (temporary stand-in, replaced by the kernel's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub t_start: f64,
    pub t_end: f64,
    pub max_depth: f64,
}

fn sampled(a: &Polygon, b: &Polygon, at: impl Fn(f64) -> super::V2) -> Vec<Contact> {
    let n = 2000;
    let mut out: Vec<Contact> = Vec::new();
    let mut open: Option<Contact> = None;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        match overlap(&a.translated(at(t)), b) {
            Some(d) => match &mut open {
                Some(c) => {
                    c.t_end = t;
                    c.max_depth = c.max_depth.max(d);
                }
                None => {
                    open = Some(Contact {
                        t_start: t,
                        t_end: t,
                        max_depth: d,
                    })
                }
            },
            None => {
                if let Some(c) = open.take() {
                    out.push(c);
                }
            }
        }
    }
    out.extend(open);
    out
}

pub fn sweep_line_episodes(a: &Polygon, b: &Polygon, d: super::V2) -> Vec<Contact> {
    sampled(a, b, |t| d * t)
}

pub fn sweep_arc_episodes(a: &Polygon, b: &Polygon, center: P2, start: P2, sweep_angle: f64) -> Vec<Contact> {
    let v = start - center;
    sampled(a, b, |t| {
        let (s, c) = (sweep_angle * t).sin_cos();
        super::V2::new(v.x * c - v.y * s, v.x * s + v.y * c) - v
    })
}
