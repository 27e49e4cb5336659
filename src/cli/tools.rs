//! `latheguard tools show` and `latheguard tools import` (docs/tools.md).

use super::args::{TableFormat, TblUnits, ToolsArgs, ToolsCommand, ToolsImportArgs, ToolsShowArgs};
use super::{emit, read_text, shown, Trouble, EXIT_CLEAN, MAX_CONFIG_BYTES};
use latheguard::geom::Polygon;
use latheguard::tooling::{self, tbl, CatalogueSpec, Decoded, DrillSpec};
use serde_json::json;
use std::fmt::Write as _;

pub fn run(a: ToolsArgs) -> Result<u8, Trouble> {
    match a.command {
        ToolsCommand::Show(a) => show(a),
        ToolsCommand::Import(a) => import(a),
    }
}

fn drill(text: &str) -> Result<DrillSpec, Trouble> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let num = |s: &str| s.parse::<f64>().map_err(|_| format!("--drill: {s:?} is not a number"));
    match parts.as_slice() {
        [d, l] => Ok(DrillSpec {
            diameter: num(d)?,
            length: num(l)?,
            point_angle: None,
        }),
        [d, l, a] => Ok(DrillSpec {
            diameter: num(d)?,
            length: num(l)?,
            point_angle: Some(num(a)?),
        }),
        _ => Err("--drill takes DIAMETER,LENGTH[,POINT_ANGLE], as in --drill 20,60,118".into()),
    }
}

/// The catalogue spec of `tools show`: CODE is an insert, or a holder when it reads as one and
/// no HOLDER follows.
fn spec_of(a: &ToolsShowArgs) -> Result<CatalogueSpec, Trouble> {
    if let Some(d) = &a.drill {
        return Ok(CatalogueSpec {
            drill: Some(drill(d)?),
            ..CatalogueSpec::default()
        });
    }
    let code = a.code.clone().unwrap_or_default();
    if a.holder.is_none() && tooling::insert::parse(&code).is_err() && tooling::holder::parse(&code).is_ok() {
        return Ok(CatalogueSpec {
            holder: Some(code),
            ..CatalogueSpec::default()
        });
    }
    Ok(CatalogueSpec {
        insert: Some(code),
        holder: a.holder.clone(),
        drill: None,
    })
}

fn num(v: f64) -> String {
    let s = format!("{:.6}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

fn round6(v: f64) -> f64 {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn points_json(p: &Polygon) -> serde_json::Value {
    json!(p
        .points()
        .iter()
        .map(|q| [round6(q.x), round6(q.y)])
        .collect::<Vec<_>>())
}

fn points_toml(p: &Polygon) -> String {
    let v: Vec<String> = p
        .points()
        .iter()
        .map(|q| format!("[{}, {}]", num(q.x), num(q.y)))
        .collect();
    format!("[{}]", v.join(", "))
}

fn show(a: ToolsShowArgs) -> Result<u8, Trouble> {
    let spec = spec_of(&a)?;
    let d = tooling::decode(&spec).map_err(|e| format!("{}: {}", e.key, e.message))?;
    if let Some(path) = &a.svg {
        std::fs::write(path, svg(&d)).map_err(|e| format!("{}: cannot write: {}", shown(path), super::plain(&e)))?;
    }
    let title = match (&spec.insert, &spec.holder, &spec.drill) {
        (_, _, Some(dr)) => format!("drill {},{}", num(dr.diameter), num(dr.length)),
        (Some(i), Some(h), _) => format!("{} + {}", i.trim(), h.trim()),
        (Some(i), None, _) => i.trim().to_string(),
        (None, Some(h), _) => h.trim().to_string(),
        _ => String::new(),
    };
    let out = match a.format {
        TableFormat::Text => {
            let mut s = format!("{title}\n");
            for (k, v) in &d.facts {
                let _ = writeln!(s, "  {k:<17} {v}");
            }
            let _ = writeln!(s, "  {:<17} {}", "summary", d.tool.summary);
            s
        }
        TableFormat::Json => {
            let facts: serde_json::Map<String, serde_json::Value> =
                d.facts.iter().map(|(k, v)| (k.to_string(), json!(v))).collect();
            let v = json!({
                "insert_code": spec.insert,
                "holder_code": spec.holder,
                "summary": d.tool.summary,
                "nose_radius": round6(d.tool.nose_radius),
                "tip_direction": d.tool.tip_direction,
                "facts": facts,
                "insert": points_json(&d.tool.insert),
                "holder": points_json(&d.tool.holder),
            });
            format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
        }
    };
    emit(None, &super::safe_lines(&out))?;
    Ok(EXIT_CLEAN)
}

/// A TOML basic string.
fn toml_string(s: &str) -> String {
    let mut o = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(o, "\\u{:04X}", c as u32);
            }
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

fn import(a: ToolsImportArgs) -> Result<u8, Trouble> {
    let name = shown(&a.file);
    let text = read_text(&a.file, MAX_CONFIG_BYTES).map_err(|why| format!("{name}: cannot read tool table: {why}"))?;
    let tools = tbl::parse(&text).map_err(|e| format!("{name}:{}:{}: {}", e.line, e.col, e.message))?;
    let inch = a.units == TblUnits::Inch;
    let mut out = format!(
        "# Tool library imported from {} (a LinuxCNC tool table in {}; lengths here in mm).\n\
         # tip = [X, Z]: the table's offsets (X a radius); nose_radius = D / 2; tip_direction = Q,\n\
         # LinuxCNC's orientation. The outlines are drawn from the front and back angles I and J\n\
         # (docs/tools.md).\n",
        toml_string(&name),
        if inch { "inches" } else { "mm" }
    );
    for t in &tools {
        let m = t.in_mm(inch);
        let d = tbl::shape(&m).map_err(|e| format!("{name}: {}", e.message))?;
        let _ = writeln!(out, "\n[[tools]]");
        let _ = writeln!(out, "id = {}", toml_string(&format!("T{}", t.tool)));
        if !t.comment.is_empty() {
            let _ = writeln!(out, "name = {}", toml_string(&t.comment));
        }
        let [x, z] = m.tip();
        let _ = writeln!(out, "tip = [{}, {}]", num(x), num(z));
        let _ = writeln!(out, "insert = {}", points_toml(&d.insert));
        let _ = writeln!(out, "holder = {}", points_toml(&d.holder));
        let _ = writeln!(out, "nose_radius = {}", num(d.nose_radius));
        let _ = writeln!(out, "tip_direction = {}", d.tip_direction);
    }
    emit(None, &out)?;
    Ok(EXIT_CLEAN)
}

/// The tool drawn as the docs draw the working plane: +z to the right, +x up; the holder grey,
/// the insert gold, the programmed point a red dot.
fn svg(d: &Decoded) -> String {
    let b = d.tool.insert.aabb().union(d.tool.holder.aabb());
    let m = 0.05 * (b.max.x - b.min.x).max(b.max.y - b.min.y) + 1.0;
    let (x0, y0) = (b.min.y - m, -b.max.x - m);
    let (w, h) = (b.max.y - b.min.y + 2.0 * m, b.max.x - b.min.x + 2.0 * m);
    let poly = |p: &Polygon, fill: &str| {
        let pts: Vec<String> = p
            .points()
            .iter()
            .map(|q| format!("{},{}", num(q.y), num(-q.x)))
            .collect();
        format!(
            "  <polygon points=\"{}\" fill=\"{fill}\" stroke=\"black\" stroke-width=\"{}\"/>\n",
            pts.join(" "),
            num(w.max(h) / 400.0)
        )
    };
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {} {}\" width=\"600\" height=\"{}\">\n",
        num(x0),
        num(y0),
        num(w),
        num(h),
        num((600.0 * h / w).clamp(50.0, 2000.0))
    );
    let _ = writeln!(s, "  <title>{}</title>", xml(&d.tool.summary));
    s.push_str(&poly(&d.tool.holder, "#bbbbbb"));
    s.push_str(&poly(&d.tool.insert, "#e8b923"));
    let _ = writeln!(
        s,
        "  <circle cx=\"0\" cy=\"0\" r=\"{}\" fill=\"red\"/>",
        num(w.max(h) / 100.0)
    );
    s.push_str("</svg>\n");
    s
}

fn xml(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}
