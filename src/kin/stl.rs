//! STL files → a validated [`Mesh`].
//!
//! Both encodings are read. A file is **binary** when its length is exactly
//! `84 + 50 × count` bytes, `count` being the little-endian 32-bit number at byte 80 — whatever
//! its first bytes say (many exporters write `solid` into a binary header). Otherwise a file that
//! starts with `solid` (after white space) is **ASCII**, and any other file is a binary one whose
//! length does not match its count (an error).
//!
//! Caps, checked before anything is sized from the file: at most [`MAX_STL_BYTES`] (128 MiB) and
//! [`MAX_STL_TRIANGLES`] (2,000,000) triangles. A binary header's count is compared with the
//! file's length before any allocation.
//!
//! Vertices are welded by exact equality of their coordinates (`-0` equals `0`). The mesh must
//! then be a closed, consistently wound surface facing outward:
//! - every coordinate is finite and within ±[`MAX_STL_COORD`] (100 m);
//! - no triangle is degenerate (two corners the same point, or all three on one line);
//! - every edge is shared by exactly two triangles that run along it in opposite directions
//!   (an edge with no partner is a hole; one used twice the same way is a flipped triangle or a
//!   non-manifold edge);
//! - the enclosed volume (divergence theorem) is positive: triangles counter-clockwise seen from
//!   outside.
//!
//! Facet normals are read (ASCII: they must be numbers) but not used: the winding decides.
//! Errors name the file and the line (ASCII) or the triangle (counting from 0), and what is
//! wrong. Reading never panics.

use std::collections::HashMap;

use nalgebra::Point3;

use super::Mesh;

/// At most this many triangles in one STL file.
pub const MAX_STL_TRIANGLES: usize = 2_000_000;
/// Every coordinate lies within ±this (mm, 100 m: the machine file's range).
pub const MAX_STL_COORD: f64 = crate::machine::MAX_COORD_MM;
/// At most this many bytes in one STL file (128 MiB).
pub const MAX_STL_BYTES: usize = 128 << 20;

/// An STL file that cannot be used.
#[derive(Clone, Debug, PartialEq)]
pub struct StlError {
    pub file: String,
    /// 1-based line of an ASCII file.
    pub line: Option<u32>,
    /// 0-based triangle index.
    pub triangle: Option<usize>,
    pub message: String,
}

impl std::fmt::Display for StlError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.line, self.triangle) {
            (Some(l), _) => write!(f, "{}:{}: {}", self.file, l, self.message),
            (None, Some(t)) => write!(f, "{}: triangle {}: {}", self.file, t, self.message),
            (None, None) => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for StlError {}

/// A triangle as read, with where it was read (the line of its `facet` in an ASCII file).
struct Soup {
    tris: Vec<[[f64; 3]; 3]>,
    lines: Option<Vec<u32>>,
}

/// Read and validate an STL file. `file` is only used in error messages.
pub fn read_stl(bytes: &[u8], file: &str) -> Result<Mesh, StlError> {
    let err = |message: String| StlError {
        file: file.to_string(),
        line: None,
        triangle: None,
        message,
    };
    if bytes.len() > MAX_STL_BYTES {
        return Err(err(format!(
            "the file is {} bytes; an STL file may have at most {MAX_STL_BYTES} (128 MiB)",
            bytes.len()
        )));
    }
    let soup = if is_binary(bytes) {
        binary(bytes, file)?
    } else if starts_with_solid(bytes) {
        ascii(bytes, file)?
    } else if bytes.len() < 84 {
        return Err(err(format!(
            "not an STL file: {} bytes, shorter than a binary STL header (84 bytes), and it does not start with `solid`",
            bytes.len()
        )));
    } else {
        let count = count_of(bytes);
        return Err(err(format!(
            "binary STL: the header says {count} triangles ({} bytes), but the file is {} bytes",
            84 + 50 * count as u64,
            bytes.len()
        )));
    };
    weld_and_validate(soup, file)
}

fn count_of(bytes: &[u8]) -> u32 {
    u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]])
}

fn is_binary(bytes: &[u8]) -> bool {
    bytes.len() >= 84 && bytes.len() as u64 == 84 + 50 * count_of(bytes) as u64
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let t = bytes.trim_ascii_start();
    t.len() >= 5 && t[..5].eq_ignore_ascii_case(b"solid")
}

fn binary(bytes: &[u8], file: &str) -> Result<Soup, StlError> {
    let count = count_of(bytes) as usize;
    if count > MAX_STL_TRIANGLES {
        return Err(StlError {
            file: file.to_string(),
            line: None,
            triangle: None,
            message: format!("{count} triangles; an STL file may have at most {MAX_STL_TRIANGLES}"),
        });
    }
    // `is_binary` held: the length matches the count, so this allocation is bounded by the file.
    let mut tris = Vec::with_capacity(count);
    for rec in bytes[84..].chunks_exact(50) {
        let f = |i: usize| {
            let o = 12 + 4 * i;
            f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]) as f64
        };
        tris.push([[f(0), f(1), f(2)], [f(3), f(4), f(5)], [f(6), f(7), f(8)]]);
    }
    Ok(Soup { tris, lines: None })
}

/// Whitespace-separated words with their 1-based lines.
struct Words<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: u32,
    /// The line of the last word read (where an unexpected end of the file is reported).
    last: u32,
}

impl<'a> Words<'a> {
    fn next(&mut self) -> Option<(&'a [u8], u32)> {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            if self.bytes[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        if self.pos >= self.bytes.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        self.last = self.line;
        Some((&self.bytes[start..self.pos], self.line))
    }

    /// The rest of the current line (a solid's name), skipped.
    fn skip_line(&mut self) {
        while self.pos < self.bytes.len() && self.bytes[self.pos] != b'\n' {
            self.pos += 1;
        }
    }
}

fn ascii(bytes: &[u8], file: &str) -> Result<Soup, StlError> {
    let mut w = Words {
        bytes,
        pos: 0,
        line: 1,
        last: 1,
    };
    let at = |line: u32, message: String| StlError {
        file: file.to_string(),
        line: Some(line),
        triangle: None,
        message,
    };
    let shown = |t: &[u8]| {
        let s = String::from_utf8_lossy(&t[..t.len().min(40)]).into_owned();
        if t.len() > 40 {
            format!("{s}…")
        } else {
            s
        }
    };
    let expect = |w: &mut Words<'_>, want: &str| -> Result<u32, StlError> {
        match w.next() {
            Some((t, l)) if t.eq_ignore_ascii_case(want.as_bytes()) => Ok(l),
            Some((t, l)) => Err(at(l, format!("expected `{want}`, found `{}`", shown(t)))),
            None => Err(at(w.last, format!("the file ends where `{want}` was expected"))),
        }
    };
    let number = |w: &mut Words<'_>, what: &str| -> Result<f64, StlError> {
        match w.next() {
            Some((t, l)) => match std::str::from_utf8(t).ok().and_then(|s| s.parse::<f64>().ok()) {
                Some(v) => Ok(v),
                None => Err(at(l, format!("{what}: `{}` is not a number", shown(t)))),
            },
            None => Err(at(w.last, format!("the file ends where {what} was expected"))),
        }
    };
    let first = expect(&mut w, "solid")?;
    w.skip_line();
    let mut tris = Vec::new();
    let mut lines = Vec::new();
    loop {
        let (t, l) = match w.next() {
            Some(x) => x,
            None => return Err(at(w.last, "the file ends without `endsolid`".into())),
        };
        if t.eq_ignore_ascii_case(b"endsolid") {
            w.skip_line();
            if let Some((t, l)) = w.next() {
                return Err(at(
                    l,
                    format!(
                        "`{}` after `endsolid` (line {first} starts the only solid a file may hold)",
                        shown(t)
                    ),
                ));
            }
            break;
        }
        if !t.eq_ignore_ascii_case(b"facet") {
            return Err(at(l, format!("expected `facet` or `endsolid`, found `{}`", shown(t))));
        }
        if tris.len() >= MAX_STL_TRIANGLES {
            return Err(at(
                l,
                format!("too many triangles; an STL file may have at most {MAX_STL_TRIANGLES}"),
            ));
        }
        expect(&mut w, "normal")?;
        for _ in 0..3 {
            number(&mut w, "a normal's coordinate")?;
        }
        expect(&mut w, "outer")?;
        expect(&mut w, "loop")?;
        let mut tri = [[0.0; 3]; 3];
        for v in tri.iter_mut() {
            expect(&mut w, "vertex")?;
            for c in v.iter_mut() {
                *c = number(&mut w, "a vertex coordinate")?;
            }
        }
        expect(&mut w, "endloop")?;
        expect(&mut w, "endfacet")?;
        tris.push(tri);
        lines.push(l);
    }
    Ok(Soup {
        tris,
        lines: Some(lines),
    })
}

fn weld_and_validate(soup: Soup, file: &str) -> Result<Mesh, StlError> {
    let err = |i: usize, message: String| StlError {
        file: file.to_string(),
        line: soup.lines.as_ref().and_then(|l| l.get(i).copied()),
        triangle: Some(i),
        message: match &soup.lines {
            Some(_) => format!("triangle {i}: {message}"),
            None => message,
        },
    };
    if soup.tris.is_empty() {
        return Err(StlError {
            file: file.to_string(),
            line: None,
            triangle: None,
            message: "no triangles: a part must be a closed surface".into(),
        });
    }
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut vertices: Vec<Point3<f64>> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(soup.tris.len());
    for (i, t) in soup.tris.iter().enumerate() {
        let mut ids = [0u32; 3];
        for (k, v) in t.iter().enumerate() {
            if let Some(c) = v.iter().find(|c| !c.is_finite()) {
                return Err(err(i, format!("corner {k} has a coordinate that is not finite ({c})")));
            }
            if let Some(c) = v.iter().find(|c| c.abs() > MAX_STL_COORD) {
                return Err(err(
                    i,
                    format!("corner {k} has a coordinate out of range ({c}): at most ±{MAX_STL_COORD} mm"),
                ));
            }
            // +0.0 so that -0 and 0 weld.
            let key = [(v[0] + 0.0).to_bits(), (v[1] + 0.0).to_bits(), (v[2] + 0.0).to_bits()];
            let next = vertices.len() as u32;
            let id = *index.entry(key).or_insert(next);
            if id == next {
                vertices.push(Point3::new(v[0], v[1], v[2]));
            }
            ids[k] = id;
        }
        let [a, b, c] = ids.map(|j| vertices[j as usize]);
        let cross = (b - a).cross(&(c - a));
        let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
        if ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2] {
            return Err(err(i, "degenerate: two of its corners are the same point".into()));
        }
        if cross.norm() <= 1e-12 * longest * longest {
            return Err(err(i, "degenerate: its three corners lie on one line".into()));
        }
        triangles.push(ids);
    }
    // Every directed edge once, and its reverse once.
    let mut edges: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * triangles.len());
    for (i, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let e = (t[k], t[(k + 1) % 3]);
            if let Some(j) = edges.insert(e, i) {
                return Err(err(
                    i,
                    format!(
                        "its edge from {} to {} runs the same way as in triangle {j}: a flipped triangle (inconsistent winding) or an edge of more than two triangles",
                        show_point(&vertices[e.0 as usize]),
                        show_point(&vertices[e.1 as usize])
                    ),
                ));
            }
        }
    }
    for (i, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if !edges.contains_key(&(b, a)) {
                return Err(err(
                    i,
                    format!(
                        "its edge from {} to {} has no neighbouring triangle: the surface is not closed",
                        show_point(&vertices[a as usize]),
                        show_point(&vertices[b as usize])
                    ),
                ));
            }
        }
    }
    let mesh = Mesh { vertices, triangles };
    let v = mesh.volume();
    if v.is_nan() || v <= 0.0 {
        return Err(StlError {
            file: file.to_string(),
            line: None,
            triangle: None,
            message: format!(
                "the enclosed volume is {v} mm³: the triangles face inward (they must run counter-clockwise seen from outside)"
            ),
        });
    }
    Ok(mesh)
}

/// The checks [`read_stl`] makes, on a mesh built in memory (welded again by exact equality):
/// closed, consistently wound, outward, no degenerate triangle.
pub fn check_mesh(mesh: &Mesh, name: &str) -> Result<(), StlError> {
    let mut tris = Vec::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        let mut tri = [[0.0; 3]; 3];
        for (k, &i) in t.iter().enumerate() {
            let Some(p) = mesh.vertices.get(i as usize) else {
                return Err(StlError {
                    file: name.to_string(),
                    line: None,
                    triangle: Some(tris.len()),
                    message: format!("vertex index {i} is out of range"),
                });
            };
            tri[k] = [p.x, p.y, p.z];
        }
        tris.push(tri);
    }
    weld_and_validate(Soup { tris, lines: None }, name).map(|_| ())
}

fn show_point(p: &Point3<f64>) -> String {
    format!("({}, {}, {})", p.x, p.y, p.z)
}

/// An STL file of `mesh`: binary (80-byte header, count, 50 bytes per triangle) or ASCII.
/// Coordinates are written as `f32`, as the format holds them.
pub fn write_stl(mesh: &Mesh, name: &str, ascii: bool) -> Vec<u8> {
    let tri = |t: &[u32; 3]| t.map(|i| mesh.vertices[i as usize]);
    let normal = |p: [Point3<f64>; 3]| {
        let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
        let l = n.norm();
        if l > 0.0 {
            n / l
        } else {
            n
        }
    };
    if ascii {
        let mut s = format!("solid {name}\n");
        for t in &mesh.triangles {
            let p = tri(t);
            let n = normal(p);
            s.push_str(&format!(
                "  facet normal {} {} {}\n    outer loop\n",
                n.x as f32, n.y as f32, n.z as f32
            ));
            for q in p {
                s.push_str(&format!("      vertex {} {} {}\n", q.x as f32, q.y as f32, q.z as f32));
            }
            s.push_str("    endloop\n  endfacet\n");
        }
        s.push_str(&format!("endsolid {name}\n"));
        return s.into_bytes();
    }
    let mut out = vec![0u8; 80];
    let head = format!("binary STL {name}");
    let n = head.len().min(80);
    out[..n].copy_from_slice(&head.as_bytes()[..n]);
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        let p = tri(t);
        let n = normal(p);
        for v in [n.x, n.y, n.z] {
            out.extend_from_slice(&(v as f32).to_le_bytes());
        }
        for q in p {
            for v in [q.x, q.y, q.z] {
                out.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit tetrahedron, outward.
    fn tetra() -> Mesh {
        Mesh {
            vertices: vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
                Point3::new(0.0, 0.0, 1.0),
            ],
            triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        }
    }

    fn msg(r: Result<Mesh, StlError>) -> String {
        r.unwrap_err().to_string()
    }

    #[test]
    fn ascii_tetrahedron_reads_and_welds_to_four_vertices() {
        let bytes = write_stl(&tetra(), "t", true);
        let m = read_stl(&bytes, "t.stl").unwrap();
        assert_eq!((m.vertices.len(), m.triangles.len()), (4, 4));
        assert!((m.volume() - 1.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn binary_tetrahedron_reads_even_with_solid_in_its_header() {
        let mut bytes = write_stl(&tetra(), "t", false);
        bytes[..5].copy_from_slice(b"solid");
        let m = read_stl(&bytes, "t.stl").unwrap();
        assert_eq!((m.vertices.len(), m.triangles.len()), (4, 4));
        assert!((m.volume() - 1.0 / 6.0).abs() < 1e-7);
    }

    #[test]
    fn binary_count_beyond_the_file_is_refused_without_allocating() {
        let mut bytes = write_stl(&tetra(), "t", false);
        bytes[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
        assert_eq!(
            msg(read_stl(&bytes, "t.stl")),
            "t.stl: binary STL: the header says 4294967295 triangles (214748364834 bytes), but the file is 284 bytes"
        );
    }

    #[test]
    fn short_garbage_is_not_an_stl_file() {
        assert!(msg(read_stl(b"hello", "x.stl")).starts_with("x.stl: not an STL file: 5 bytes"));
        assert!(msg(read_stl(b"", "x.stl")).contains("0 bytes"));
    }

    #[test]
    fn a_missing_triangle_is_a_hole_named_by_triangle() {
        let mut m = tetra();
        m.triangles.pop();
        let e = msg(read_stl(&write_stl(&m, "t", false), "t.stl"));
        assert!(e.starts_with("t.stl: triangle 0: its edge from"), "{e}");
        assert!(
            e.ends_with("has no neighbouring triangle: the surface is not closed"),
            "{e}"
        );
    }

    #[test]
    fn a_flipped_triangle_is_named_with_its_ascii_line() {
        let mut m = tetra();
        m.triangles[2] = [1, 3, 2];
        let e = msg(read_stl(&write_stl(&m, "t", true), "t.stl"));
        // Triangle 2's facet starts on line 2 + 2 × 7.
        assert!(e.starts_with("t.stl:16: triangle 2: its edge from"), "{e}");
        assert!(e.contains("runs the same way as in triangle"), "{e}");
    }

    #[test]
    fn an_inside_out_mesh_is_refused() {
        let mut m = tetra();
        for t in &mut m.triangles {
            t.swap(1, 2);
        }
        let e = msg(read_stl(&write_stl(&m, "t", false), "t.stl"));
        assert!(e.contains("the triangles face inward"), "{e}");
    }

    #[test]
    fn degenerate_triangles_are_named() {
        let mut m = tetra();
        m.vertices[3] = Point3::new(0.5, 0.5, 0.0);
        let e = msg(read_stl(&write_stl(&m, "t", false), "t.stl"));
        assert_eq!(e, "t.stl: triangle 2: degenerate: its three corners lie on one line");
        let mut m = tetra();
        m.triangles[1] = [0, 1, 1];
        let e = msg(read_stl(&write_stl(&m, "t", false), "t.stl"));
        assert_eq!(
            e,
            "t.stl: triangle 1: degenerate: two of its corners are the same point"
        );
    }

    #[test]
    fn non_finite_coordinates_are_refused() {
        let text =
            String::from_utf8(write_stl(&tetra(), "t", true))
                .unwrap()
                .replacen("vertex 0 0 0", "vertex nan 0 0", 1);
        let e = msg(read_stl(text.as_bytes(), "t.stl"));
        assert_eq!(
            e,
            "t.stl:2: triangle 0: corner 0 has a coordinate that is not finite (NaN)"
        );
    }

    #[test]
    fn ascii_syntax_errors_name_the_line() {
        let text = "solid x\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 zero\n";
        assert_eq!(
            msg(read_stl(text.as_bytes(), "a.stl")),
            "a.stl:4: a vertex coordinate: `zero` is not a number"
        );
        assert_eq!(
            msg(read_stl(b"solid x\n facet normal 0 0 1\n outer loop\n", "a.stl")),
            "a.stl:3: the file ends where `vertex` was expected"
        );
        assert_eq!(
            msg(read_stl(b"solid x\n", "a.stl")),
            "a.stl:1: the file ends without `endsolid`"
        );
        assert_eq!(
            msg(read_stl(b"solid x\nendsolid x\n", "a.stl")),
            "a.stl: no triangles: a part must be a closed surface"
        );
        let two = [write_stl(&tetra(), "a", true), write_stl(&tetra(), "b", true)].concat();
        assert!(msg(read_stl(&two, "a.stl")).contains("after `endsolid`"));
    }

    #[test]
    fn hostile_bytes_never_panic() {
        let base = write_stl(&tetra(), "t", true);
        for cut in 0..base.len() {
            let _ = read_stl(&base[..cut], "t.stl");
        }
        let bin = write_stl(&tetra(), "t", false);
        for i in 0..bin.len() {
            let mut b = bin.clone();
            b[i] ^= 0xA5;
            let _ = read_stl(&b, "t.stl");
        }
    }
}
