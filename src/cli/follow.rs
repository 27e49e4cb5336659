//! `latheguard follow`: live samples in, findings out as they happen (docs/follow.md). The
//! library (`latheguard::follow`) reads and checks each sample; this reads the source line by
//! line, writes and flushes each finding, and measures the time each sample takes.

use super::args::{FollowArgs, FollowFormat, JobArgs, SamplesFormat};
use super::{plain, shown, Trouble, EXIT_CLEAN, EXIT_FINDINGS};
use latheguard::finding::{Finding, Severity};
use latheguard::follow::{sample, Follower, Latency, SampleError};
use latheguard::report::{finding_json, finding_text, terminal_safe};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::time::Instant;

pub fn run(a: FollowArgs) -> Result<u8, Trouble> {
    let job = JobArgs {
        job: a.job.clone(),
        no_assume: true,
        ..JobArgs::default()
    };
    // With --program: the setup `check` gives that program (its latheguard.toml, the job beside
    // it); else the machine of -m (or the built-in one) and --job.
    let (program, no_config) = match &a.program {
        Some(p) => (p.as_path(), false),
        None => (Path::new("-"), true),
    };
    let resolved = super::setup::Planner::new(a.machine.as_deref(), no_config, &job)?.resolve(program)?;
    let machine = resolved.machine;
    let mut settings = resolved.settings;
    if a.clearance > 0.0 {
        settings.clearance_mm = a.clearance;
    }
    if let Some(d) = a.min_depth {
        settings.min_depth_mm = Some(d);
    }
    if let Some(t) = a.tolerance {
        settings.tolerance_mm = t;
    }
    let input = open(a.source.as_deref().unwrap_or("-"))?;
    // Each path's carrier on its own lathe (one on a one-path machine), and on a machine with
    // several paths the carriers against each other (docs/follow.md).
    let lathes = latheguard::follow::lathes(&machine);
    let mut follower = Follower::new(&machine, &lathes, &settings);
    let format = match a.samples {
        SamplesFormat::Auto => sample::Format::Auto,
        SamplesFormat::Json => sample::Format::Json,
        SamplesFormat::Csv => sample::Format::Csv,
    };
    let mut reader = follower.reader(format);
    if let Some(p) = a.period {
        reader = reader.with_period(p);
    }
    let source = a.source.as_deref().filter(|s| *s != "-").unwrap_or("<stdin>");
    let source = terminal_safe(source).into_owned();
    let mut out = Out {
        w: std::io::BufWriter::new(std::io::stdout().lock()),
        json: a.format == FollowFormat::Json,
        source,
        errors: 0,
        rejected: 0,
        closed: false,
    };
    let mut latency = Latency::default();
    let mut input = BufReader::with_capacity(1 << 16, input);
    let mut buf = Vec::with_capacity(256);
    let mut line_no = 0u64;
    loop {
        buf.clear();
        let got = read_line(&mut input, &mut buf).map_err(|e| format!("{}: cannot read: {}", out.source, plain(&e)))?;
        if got == Got::End {
            break;
        }
        line_no += 1;
        let start = Instant::now();
        let result = match (got, std::str::from_utf8(&buf)) {
            (Got::TooLong, _) => Err(SampleError {
                line: line_no,
                col: 0,
                message: format!("the line is longer than {} bytes", sample::MAX_LINE),
            }),
            (_, Err(_)) => Err(SampleError {
                line: line_no,
                col: 0,
                message: "the line is not UTF-8 text".into(),
            }),
            (_, Ok(text)) => match reader.read(line_no, text.trim_end_matches('\n')) {
                Ok(None) => continue,
                Ok(Some(s)) => follower.push(line_no, &s, reader.period()).map(|_| ()),
                Err(e) => Err(e),
            },
        };
        let findings = follower.findings();
        latency.add(start.elapsed().as_nanos().min(u128::from(u64::MAX)) as u64);
        if let Err(e) = result {
            out.sample_error(&e)?;
        }
        for f in &findings {
            out.finding(f)?;
        }
        if out.closed {
            break;
        }
    }
    let machine_time = follower.time().unwrap_or(0.0);
    let (rest, stats) = follower.finish();
    for f in &rest {
        out.finding(f)?;
    }
    if a.stats {
        let s = latency.summary();
        let line = format!(
            "follow: {} samples, {} moves checked, {:.3} s of machine time; per sample: median {:.1} µs, p99 {:.1} µs, max {:.1} µs, mean {:.1} µs; {} pair tests",
            s.samples, stats.moves, machine_time, s.median_us, s.p99_us, s.max_us, s.mean_us, stats.pair_tests
        );
        if out.json {
            let doc =
                serde_json::json!({"summary": {"latency": s, "moves": stats.moves, "pair_tests": stats.pair_tests}});
            out.write(&doc.to_string())?;
        }
        super::say(&line);
    }
    out.flush()?;
    // A rejected sample is an `error[sample]` of the input, as a program line that cannot be
    // read is a finding of its file: status 1, not a failure of the run.
    Ok(if out.errors > 0 || out.rejected > 0 {
        EXIT_FINDINGS
    } else {
        EXIT_CLEAN
    })
}

struct Out<W: Write> {
    w: W,
    json: bool,
    source: String,
    /// Findings of severity error written.
    errors: u64,
    /// Samples rejected.
    rejected: u64,
    /// Standard output is a closed pipe: stop reading.
    closed: bool,
}

impl<W: Write> Out<W> {
    fn write(&mut self, line: &str) -> Result<(), Trouble> {
        if self.closed {
            return Ok(());
        }
        match writeln!(self.w, "{line}").and_then(|_| self.w.flush()) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
                self.closed = true;
                Ok(())
            }
            Err(e) => Err(format!("cannot write to standard output: {}", plain(&e))),
        }
    }

    fn flush(&mut self) -> Result<(), Trouble> {
        match self.w.flush() {
            Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                Err(format!("cannot write to standard output: {}", plain(&e)))
            }
            _ => Ok(()),
        }
    }

    fn finding(&mut self, f: &Finding) -> Result<(), Trouble> {
        if f.severity == Severity::Error {
            self.errors += 1;
        }
        let line = if self.json {
            finding_json(f)
        } else {
            let at = if f.line > 0 {
                format!("line {}", f.line)
            } else {
                "no line".to_string()
            };
            format!("{}: {at}: {}", self.source, finding_text(f))
        };
        self.write(&line)
    }

    fn sample_error(&mut self, e: &SampleError) -> Result<(), Trouble> {
        self.rejected += 1;
        let line = if self.json {
            serde_json::json!({
                "kind": "sample",
                "severity": "error",
                "input_line": e.line,
                "column": (e.col > 0).then_some(e.col),
                "message": e.message,
            })
            .to_string()
        } else {
            format!(
                "{}:{}: error[sample]: {}",
                self.source,
                if e.col > 0 {
                    format!("{}:{}", e.line, e.col)
                } else {
                    e.line.to_string()
                },
                terminal_safe(&e.message)
            )
        };
        self.write(&line)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Got {
    Line,
    TooLong,
    End,
}

/// Read one line into `buf` (without its `\n`), at most [`sample::MAX_LINE`] bytes kept: a
/// longer line is read to its end and dropped.
fn read_line(r: &mut impl BufRead, buf: &mut Vec<u8>) -> std::io::Result<Got> {
    let cap = sample::MAX_LINE as u64 + 1;
    let n = r.by_ref().take(cap).read_until(b'\n', buf)?;
    if n == 0 {
        return Ok(Got::End);
    }
    if buf.last() == Some(&b'\n') {
        buf.pop();
        return Ok(Got::Line);
    }
    if buf.len() as u64 <= sample::MAX_LINE as u64 {
        // The last line, without a newline.
        return Ok(Got::Line);
    }
    // Skip the rest of the long line.
    loop {
        let (done, used) = {
            let chunk = r.fill_buf()?;
            if chunk.is_empty() {
                (true, 0)
            } else {
                match chunk.iter().position(|&b| b == b'\n') {
                    Some(i) => (true, i + 1),
                    None => (false, chunk.len()),
                }
            }
        };
        r.consume(used);
        if done {
            buf.clear();
            return Ok(Got::TooLong);
        }
    }
}

/// The source of samples: standard input, a file, `tcp:HOST:PORT` or `unix:PATH`.
fn open(source: &str) -> Result<Box<dyn Read>, Trouble> {
    if source == "-" {
        return Ok(Box::new(std::io::stdin()));
    }
    if let Some(addr) = source.strip_prefix("tcp:") {
        let s = std::net::TcpStream::connect(addr)
            .map_err(|e| format!("{}: cannot connect: {}", terminal_safe(source), plain(&e)))?;
        let _ = s.set_nodelay(true);
        return Ok(Box::new(s));
    }
    if let Some(path) = source.strip_prefix("unix:") {
        #[cfg(unix)]
        {
            let s = std::os::unix::net::UnixStream::connect(path)
                .map_err(|e| format!("{}: cannot connect: {}", terminal_safe(source), plain(&e)))?;
            return Ok(Box::new(s));
        }
        #[cfg(not(unix))]
        {
            let _ = path;
            return Err(format!(
                "{}: Unix sockets are not available here",
                terminal_safe(source)
            ));
        }
    }
    let p = Path::new(source);
    // A FIFO is a live feed too (`mkfifo`, a sampler writing into it): opened and read as it comes.
    let f = std::fs::File::open(p).map_err(|e| format!("{}: cannot read: {}", shown(p), plain(&e)))?;
    if f.metadata().is_ok_and(|m| m.is_dir()) {
        return Err(format!("{}: cannot read: it is a folder", shown(p)));
    }
    Ok(Box::new(f))
}
