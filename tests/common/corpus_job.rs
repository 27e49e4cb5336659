//! Interim job applier for `tests/corpus_setups.rs`, until the job module lands (issue 13; the
//! format is the lead's job spec). It merges a job file into a machine file at the TOML level —
//! the job's `[stock]` and `[chuck]` replace the machine's as whole tables, `[[tools]]` replace
//! the machine's tool of the same station, `units`, `dialect` and `program_zero_z` go to
//! `[machine]` and `[setup]`, `[tailstock] in_use = false` removes the tailstock and `true`
//! advances it at start — and reads the merged text with `latheguard::machine::from_toml`, so
//! every outline and number goes through the machine file's own validation.
//!
//! Catalogue strings (`insert = "CNMG 120408"`), `drill`, `use`, `tbl`, `tool_library` and
//! `tool_table` are not decoded here: a job for this applier gives outlines and names the ISO
//! codes it means in a comment. Such a key is an error, never silently ignored.
#![allow(dead_code)]

use latheguard::machine::{self, Machine};
use toml::{Table, Value};

/// Keys of a job this applier understands, at the top level and per table.
const TOP: &[&str] = &[
    "units",
    "dialect",
    "program_zero_z",
    "stock",
    "chuck",
    "tailstock",
    "tools",
];
const STOCK: &[&str] = &["diameter", "length", "stick_out", "front", "bore"];
const TOOL: &[&str] = &[
    "station",
    "name",
    "tip",
    "insert",
    "holder",
    "nose_radius",
    "tip_direction",
];

fn check_keys(t: &Table, allowed: &[&str], what: &str) -> Result<(), String> {
    for k in t.keys() {
        if !allowed.contains(&k.as_str()) {
            return Err(format!("{what}: key `{k}` is not understood by the interim applier"));
        }
    }
    Ok(())
}

fn table<'a>(v: &'a Value, what: &str) -> Result<&'a Table, String> {
    v.as_table().ok_or_else(|| format!("{what} must be a table"))
}

/// The machine file text with the job merged in (a machine file `latheguard --machine` reads).
pub fn merged_toml(machine_toml: &str, job_toml: &str) -> Result<String, String> {
    let mut m: Table = machine_toml.parse().map_err(|e| format!("machine: {e}"))?;
    let job: Table = job_toml.parse().map_err(|e| format!("job: {e}"))?;
    check_keys(&job, TOP, "job")?;
    let section = |m: &mut Table, name: &str| -> Table {
        match m.remove(name) {
            Some(Value::Table(t)) => t,
            _ => Table::new(),
        }
    };
    for key in ["units", "dialect"] {
        if let Some(v) = job.get(key) {
            let mut t = section(&mut m, "machine");
            t.insert(key.into(), v.clone());
            m.insert("machine".into(), Value::Table(t));
        }
    }
    let mut front = None;
    if let Some(v) = job.get("stock") {
        let s = table(v, "[stock]")?;
        check_keys(s, STOCK, "[stock]")?;
        let mut out = Table::new();
        for (k, v) in s {
            let k = if k == "stick_out" { "front" } else { k.as_str() };
            out.insert(k.into(), v.clone());
        }
        front = out.get("front").cloned();
        m.insert("stock".into(), Value::Table(out));
    }
    // Program zero: the job's, else the job stock's front face, else the machine's.
    if let Some(z) = job.get("program_zero_z").cloned().or(front) {
        let mut t = section(&mut m, "setup");
        t.insert("program_zero_z".into(), z);
        m.insert("setup".into(), Value::Table(t));
    }
    if let Some(v) = job.get("chuck") {
        let c = table(v, "[chuck]")?;
        check_keys(c, &["outline"], "[chuck]")?;
        m.insert("chuck".into(), Value::Table(c.clone()));
    }
    if let Some(v) = job.get("tailstock") {
        let t = table(v, "[tailstock]")?;
        check_keys(t, &["in_use"], "[tailstock]")?;
        match t.get("in_use").and_then(Value::as_bool) {
            Some(false) => {
                m.remove("tailstock");
            }
            Some(true) => {
                let mut ts = section(&mut m, "tailstock");
                if ts.get("outline").is_none() {
                    return Err("[tailstock] in_use = true on a machine without a tailstock".into());
                }
                ts.insert("advanced".into(), Value::Boolean(true));
                m.insert("tailstock".into(), Value::Table(ts));
            }
            None => return Err("[tailstock] in_use must be true or false".into()),
        }
    }
    if let Some(v) = job.get("tools") {
        let list = v.as_array().ok_or("[[tools]] must be an array of tables")?;
        let mut tools: Vec<Value> = match m.remove("tools") {
            Some(Value::Array(a)) => a,
            _ => Vec::new(),
        };
        for t in list {
            let t = table(t, "[[tools]]")?;
            check_keys(t, TOOL, "[[tools]]")?;
            for k in ["insert", "holder"] {
                if t.get(k).is_some_and(Value::is_str) {
                    return Err(format!(
                        "[[tools]] {k}: catalogue strings are not decoded yet; give an outline"
                    ));
                }
            }
            let station = t
                .get("station")
                .and_then(Value::as_integer)
                .ok_or("[[tools]] needs a station")?;
            tools.retain(|x| x.get("station").and_then(Value::as_integer) != Some(station));
            tools.push(Value::Table(t.clone()));
        }
        tools.sort_by_key(|x| x.get("station").and_then(Value::as_integer));
        m.insert("tools".into(), Value::Array(tools));
    }
    Ok(emit(&m))
}

/// The machine file at `machine_toml` (named `machine_name` in messages) with the job applied.
pub fn apply(machine_toml: &str, machine_name: &str, job_toml: &str) -> Result<Machine, String> {
    let text = merged_toml(machine_toml, job_toml)?;
    machine::from_toml(&text, machine_name).map_err(|e| format!("{machine_name} with the job: {e}"))
}

/// TOML text of a machine table: plain tables as `[name]` sections, arrays of tables as
/// `[[name]]` blocks, everything else inline.
fn emit(m: &Table) -> String {
    let mut out = String::new();
    for (k, v) in m {
        if !v.is_table() && !is_table_array(v) {
            out += &format!("{k} = {}\n", inline(v));
        }
    }
    for (k, v) in m {
        if let Value::Table(t) = v {
            out += &format!("\n[{k}]\n");
            for (k2, v2) in t {
                out += &format!("{k2} = {}\n", inline(v2));
            }
        }
    }
    for (k, v) in m {
        if is_table_array(v) {
            for t in v.as_array().unwrap() {
                out += &format!("\n[[{k}]]\n");
                for (k2, v2) in t.as_table().unwrap() {
                    out += &format!("{k2} = {}\n", inline(v2));
                }
            }
        }
    }
    out
}

fn is_table_array(v: &Value) -> bool {
    v.as_array()
        .is_some_and(|a| !a.is_empty() && a.iter().all(Value::is_table))
}

fn inline(v: &Value) -> String {
    match v {
        Value::String(s) => serde_json::to_string(s).unwrap(),
        Value::Integer(i) => i.to_string(),
        Value::Float(f) => format!("{f:?}"),
        Value::Boolean(b) => b.to_string(),
        Value::Datetime(d) => d.to_string(),
        Value::Array(a) => format!("[{}]", a.iter().map(inline).collect::<Vec<_>>().join(", ")),
        Value::Table(t) => format!(
            "{{ {} }}",
            t.iter()
                .map(|(k, v)| format!("{k} = {}", inline(v)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}
