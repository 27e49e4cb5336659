//! Helpers shared by the geometry tests.

use crate::geom::{orient, p2, P2, V2};

pub fn pts(v: &[(f64, f64)]) -> Vec<P2> {
    v.iter().map(|&(x, y)| p2(x, y)).collect()
}

pub fn shifted(v: &[P2], s: V2) -> Vec<P2> {
    v.iter().map(|p| p + s).collect()
}

/// The same outline written differently: reversed winding, another start vertex, repeated
/// points, and exactly collinear points inserted (only where the midpoint is exactly on the edge).
pub fn rewritings(v: &[P2]) -> Vec<(&'static str, Vec<P2>)> {
    let n = v.len();
    let mut out = vec![("as given", v.to_vec())];
    let mut r = v.to_vec();
    r.reverse();
    out.push(("reversed", r));
    let k = n / 2 + 1;
    out.push(("rotated start", (0..n).map(|i| v[(i + k) % n]).collect()));
    let mut d = Vec::new();
    for (i, p) in v.iter().enumerate() {
        d.push(*p);
        if i % 2 == 0 {
            d.push(*p);
        }
    }
    d.push(v[0]); // closing point repeated
    out.push(("duplicates", d));
    let mut c = Vec::new();
    for i in 0..n {
        let (a, b) = (v[i], v[(i + 1) % n]);
        c.push(a);
        let m = P2::from((a.coords + b.coords) * 0.5);
        if orient(a, b, m) == 0.0 && m != a && m != b {
            c.push(m);
            let q = P2::from((m.coords + b.coords) * 0.5);
            if orient(a, b, q) == 0.0 && q != m && q != b {
                c.push(q);
            }
        }
    }
    out.push(("collinear points", c));
    let mut rc: Vec<P2> = out.last().unwrap().1.clone();
    rc.reverse();
    rc.rotate_left(1);
    out.push(("reversed with collinear points", rc));
    out
}

/// Proptest configuration with `n` cases, unless `PROPTEST_CASES` asks for another number
/// (e.g. `PROPTEST_CASES=20000 cargo test --release geom` for a long run).
pub fn cases(n: u32) -> proptest::test_runner::Config {
    let mut c = proptest::test_runner::Config::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = n;
    }
    c
}
