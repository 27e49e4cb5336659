//! The SVG pictures render readably in the two renderers people convert them with:
//! `rsvg-convert` (librsvg) and `cairosvg`. A 2D finding picture, a machine drawing and a final
//! part's drawing (`--stock-out part.svg`) made now by the binary, and the three views of a 3D
//! finding (`docs/pictures/turn-mill-views.svg`, which `report3d.rs` keeps equal to what the
//! views draw today), each rendered to PNG by every
//! renderer: the PNG decodes, has the picture's size, is not blank, and its caption is drawn in
//! dark ink on the white page (not white on white).
//!
//! A renderer missing from the PATH fails the test, naming what to install, unless
//! `LATHEGUARD_SKIP_RENDER=1` is set (`.ci/run` installs both; docs/testing.md).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A renderer: its name, how to install it, and the command turning `svg` into `png`.
struct Renderer {
    name: &'static str,
    install: &'static str,
    present: fn() -> bool,
    render: fn(&Path, &Path) -> Command,
}

const CAIRO_SCRIPT: &str = "import sys, cairosvg; cairosvg.svg2png(url=sys.argv[1], write_to=sys.argv[2])";

const RENDERERS: [Renderer; 2] = [
    Renderer {
        name: "rsvg-convert",
        install: "apt-get install librsvg2-bin",
        present: || runs(Command::new("rsvg-convert").arg("--version")),
        render: |svg, png| {
            let mut c = Command::new("rsvg-convert");
            c.arg("--format=png").arg("--output").arg(png).arg(svg);
            c
        },
    },
    Renderer {
        name: "cairosvg",
        install: "python3 -m pip install cairosvg",
        present: || runs(Command::new("python3").args(["-c", "import cairosvg"])),
        render: |svg, png| {
            let mut c = Command::new("python3");
            c.args(["-c", CAIRO_SCRIPT]).arg(svg).arg(png);
            c
        },
    },
];

fn runs(c: &mut Command) -> bool {
    c.output().is_ok_and(|o| o.status.success())
}

/// The pictures to render: a 2D finding picture, a machine drawing and a part drawing written by
/// the binary into `dir`, and the committed 3D views page.
fn pictures(dir: &Path) -> Vec<PathBuf> {
    let bin = env!("CARGO_BIN_EXE_latheguard");
    let findings = dir.join("findings");
    let out = Command::new(bin)
        .current_dir(root())
        .args(["check", "--quiet", "--svg"])
        .arg(&findings)
        .arg("programs/crash_rapid_into_bar.nc")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let mut finding: Vec<PathBuf> = std::fs::read_dir(&findings)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .collect();
    assert_eq!(finding.len(), 1, "{finding:?}");
    let drawing = dir.join("machine.svg");
    let out = Command::new(bin)
        .current_dir(root())
        .args(["machine", "--svg"])
        .arg(&drawing)
        .arg("machines/generic-slant-bed.toml")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let part = dir.join("part.svg");
    let out = Command::new(bin)
        .current_dir(root())
        .args(["check", "--quiet", "programs/od_turning.nc", "--stock-out"])
        .arg(&part)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    vec![
        finding.remove(0),
        drawing,
        part,
        root().join("docs/pictures/turn-mill-views.svg"),
    ]
}

/// The `width` and `height` of the SVG's root, in pixels.
fn size_of(svg: &Path) -> (u32, u32) {
    let text = std::fs::read_to_string(svg).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let dim = |k: &str| -> u32 {
        let v = doc
            .root_element()
            .attribute(k)
            .unwrap_or_else(|| panic!("{}: no {k}", svg.display()));
        v.trim_end_matches("px").parse::<f64>().unwrap().round() as u32
    };
    (dim("width"), dim("height"))
}

/// A decoded PNG as 8-bit RGBA rows.
struct Image {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
}

fn decode(png_path: &Path) -> Image {
    let file = std::fs::File::open(png_path).unwrap();
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::normalize_to_color8() | png::Transformations::ALPHA);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let rgba = match info.color_type {
        png::ColorType::Rgba => buf,
        png::ColorType::GrayscaleAlpha => buf.chunks(2).flat_map(|p| [p[0], p[0], p[0], p[1]]).collect(),
        other => panic!("{}: unexpected colour type {other:?}", png_path.display()),
    };
    Image {
        width: info.width,
        height: info.height,
        rgba,
    }
}

impl Image {
    /// The pixel at (x, y) composed over white, as (r, g, b).
    fn at(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        let p = &self.rgba[i..i + 4];
        let a = p[3] as u32;
        let over = |c: u8| ((c as u32 * a + 255 * (255 - a)) / 255) as u8;
        [over(p[0]), over(p[1]), over(p[2])]
    }

    /// How many pixels of rows `rows` satisfy `f`.
    fn count(&self, rows: std::ops::Range<u32>, f: impl Fn([u8; 3]) -> bool) -> usize {
        rows.flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .filter(|&(x, y)| f(self.at(x, y)))
            .count()
    }
}

/// Dark ink: the captions' text colours (#1f2328, #57606a) and darker.
fn dark(p: [u8; 3]) -> bool {
    p.iter().all(|&c| c < 120)
}

/// Checks one rendered picture; Err says what is wrong with it.
fn readable(png_path: &Path, (w, h): (u32, u32)) -> Result<(), String> {
    let img = decode(png_path);
    if (img.width, img.height) != (w, h) {
        return Err(format!("{}×{} pixels, the SVG says {w}×{h}", img.width, img.height));
    }
    let all = (img.width * img.height) as usize;
    let inked = img.count(0..img.height, |p| p != [255, 255, 255]);
    if inked * 100 < all {
        return Err(format!("blank: {inked} of {all} pixels are not white"));
    }
    // The caption (the place, the message, the figures) is in the top 100 pixels.
    let caption = img.count(0..100.min(img.height), dark);
    if caption < 300 {
        return Err(format!(
            "the caption is not readable: {caption} dark pixels in the top 100 rows"
        ));
    }
    let rows = 100.min(img.height);
    let white = img.count(0..rows, |p| p == [255, 255, 255]);
    if white * 2 < (rows * img.width) as usize {
        return Err(format!(
            "the caption is not on a white page: {white} white pixels in the top 100 rows"
        ));
    }
    Ok(())
}

#[test]
fn pictures_render_readably_in_rsvg_convert_and_cairosvg() {
    let skip = std::env::var("LATHEGUARD_SKIP_RENDER").is_ok_and(|v| v == "1");
    let dir = tempfile::tempdir().unwrap();
    let pictures = pictures(dir.path());
    let mut failures = Vec::new();
    let mut rendered = 0;
    for r in &RENDERERS {
        if !(r.present)() {
            if skip {
                eprintln!(
                    "render_png: {} is not installed: skipped (LATHEGUARD_SKIP_RENDER=1)",
                    r.name
                );
                continue;
            }
            panic!(
                "{} is not installed, so the pictures cannot be checked in it: {} (or set LATHEGUARD_SKIP_RENDER=1 to skip this renderer knowingly)",
                r.name, r.install
            );
        }
        for svg in &pictures {
            let stem = svg.file_stem().unwrap().to_string_lossy();
            let png_path = dir.path().join(format!("{}.{stem}.png", r.name));
            let out = (r.render)(svg, &png_path).output().unwrap();
            let name = svg.file_name().unwrap().to_string_lossy();
            if !out.status.success() {
                failures.push(format!(
                    "{} failed on {name}: {}",
                    r.name,
                    String::from_utf8_lossy(&out.stderr)
                ));
                continue;
            }
            rendered += 1;
            if let Err(why) = readable(&png_path, size_of(svg)) {
                failures.push(format!("{} on {name}: {why}", r.name));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    if !skip {
        assert_eq!(rendered, RENDERERS.len() * pictures.len());
    }
}

/// The checks can fail: a caption in white ink on the white page and a blank page are refused.
#[test]
fn a_white_on_white_caption_and_a_blank_page_are_not_readable() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, w: u32, h: u32, pixel: &dyn Fn(u32, u32) -> [u8; 3]| {
        let path = dir.path().join(name);
        let file = std::fs::File::create(&path).unwrap();
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut data = Vec::new();
        for y in 0..h {
            for x in 0..w {
                data.extend(pixel(x, y));
            }
        }
        enc.write_header().unwrap().write_image_data(&data).unwrap();
        path
    };
    // A drawing below, the caption rows white.
    let drawing = |x: u32, y: u32| {
        if y > 150 && (x + y) % 3 == 0 {
            [30, 30, 30]
        } else {
            [255, 255, 255]
        }
    };
    let white_caption = write("white.png", 200, 400, &drawing);
    let e = readable(&white_caption, (200, 400)).unwrap_err();
    assert!(e.contains("caption is not readable"), "{e}");
    let blank = write("blank.png", 200, 400, &|_, _| [255, 255, 255]);
    assert!(readable(&blank, (200, 400)).unwrap_err().contains("blank"));
    let captioned = write("ok.png", 200, 400, &|x, y| {
        if y < 100 && (x + y) % 4 == 0 {
            [31, 35, 40]
        } else {
            drawing(x, y)
        }
    });
    assert_eq!(readable(&captioned, (200, 400)), Ok(()));
    assert!(readable(&captioned, (201, 400))
        .unwrap_err()
        .contains("the SVG says 201×400"));
}
