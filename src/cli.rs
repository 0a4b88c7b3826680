//! The command line: `cwsynth solve`, `cwsynth check`. Thin: parsing arguments, calling
//! the library, printing; errors get context here (anyhow), typed errors live below.

use crate::families::solve_scene;
use crate::families::{self, Scene};
use crate::report::{fmt_num, write_outputs, SolveResult, Status};
use anyhow::Context;
use clap::{CommandFactory, Parser, Subcommand};
use std::path::{Path, PathBuf};

/// Optimisation-driven counterweight and mechanism synthesis.
#[derive(Debug, Parser)]
#[command(name = "cwsynth", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve problem files (or every *.toml in given directories) and report.
    #[command(
        after_help = "Examples:\n  cwsynth solve problems/piston-1000rpm.toml\n  cwsynth solve problems/ --out results/\n  cwsynth solve --json my.toml > my.json\n  cat my.toml | cwsynth solve -"
    )]
    Solve {
        /// Problem files or directories; `-` reads one problem file from standard input.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Print each scene's result as one JSON object on one line (JSON Lines, the same
        /// shape for one file or many) instead of a summary.
        #[arg(long)]
        json: bool,
        /// Write `<name>.json`, `<name>.md` and SVG plots into this directory.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Units of the written reports (Markdown, HTML): `workshop` (mm, °, rpm, kN) or `si`
        /// (as the JSON, which is always SI).
        #[arg(long, value_enum, default_value_t = UnitsArg::Workshop)]
        units: UnitsArg,
    },
    /// Solve many machines: problem files, directories, fleets `TEMPLATE.toml:FLEET.csv`
    /// (docs/batch.md). Writes per-machine results, summary.csv, summary.md, index.html.
    #[command(
        after_help = "Examples:\n  cwsynth batch problems/ --out results/\n  cwsynth batch problems/piston-1000rpm.toml:fleet.csv --summary-only --out fleet/\n  cwsynth batch problems/piston-1000rpm.toml:fleet.csv --shard 0/4 --out part0/"
    )]
    Batch {
        /// Problem files, directories of them, or fleets `TEMPLATE.toml:FLEET.csv`.
        inputs: Vec<String>,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Worker threads, 1–1024 (default: all cores).
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..=1024))]
        threads: Option<u16>,
        /// Only machines with index % n == i, e.g. `--shard 0/4`, or `--shard auto` (the
        /// array index of a Slurm job array or a Kubernetes Indexed Job, docs/batch.md);
        /// writes `summary-shard-i-of-n.csv` (join them with `--merge` or `cwsynth merge`).
        #[arg(long)]
        shard: Option<String>,
        /// No progress output.
        #[arg(long)]
        quiet: bool,
        /// Write only summary.csv/md and index.html, no per-machine files (large fleets).
        #[arg(long)]
        summary_only: bool,
        /// Join the shard summaries in --out (after all shards ran) instead of solving.
        #[arg(long)]
        merge: bool,
        /// Units of the written reports (Markdown, HTML): `workshop` (mm, °, rpm, kN) or `si`
        /// (as the JSON, which is always SI).
        #[arg(long, value_enum, default_value_t = UnitsArg::Workshop)]
        units: UnitsArg,
    },
    /// Join shard summaries (`summary-shard-i-of-n.csv` in the given directories).
    #[command(after_help = "Example:\n  cwsynth merge part0/ part1/ part2/ part3/ --out fleet/")]
    Merge {
        /// Directories holding shard summaries.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Where to write summary.csv, summary.md and index.html.
        #[arg(long)]
        out: PathBuf,
    },
    /// Validate problem files without solving (`-` reads one from standard input).
    #[command(after_help = "Examples:\n  cwsynth check problems/\n  cwsynth check - < my.toml")]
    Check {
        /// Problem files or directories; `-` reads one problem file from standard input.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
    },
    /// Print the JSON Schema (draft 2020-12) of the problem file, every family.
    #[command(after_help = "Example:\n  cwsynth schema > cwsynth.schema.json")]
    Schema,
    /// Print a commented problem file of a family to start from
    /// (`cwsynth new slider-crank > my.toml && cwsynth solve my.toml`).
    #[command(
        after_help = "Example:\n  cwsynth new linkage > press.toml && cwsynth solve press.toml"
    )]
    New {
        /// The family.
        #[arg(value_parser = clap::builder::PossibleValuesParser::new(family_names()))]
        family: String,
    },
    /// Print a shell completion script (e.g. `cwsynth completions bash >
    /// ~/.local/share/bash-completion/completions/cwsynth`).
    #[command(
        after_help = "Example:\n  cwsynth completions bash > ~/.local/share/bash-completion/completions/cwsynth"
    )]
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
    /// Print the manual page (roff; `cwsynth man > cwsynth.1 && man ./cwsynth.1`).
    #[command(after_help = "Example:\n  cwsynth man > cwsynth.1 && man ./cwsynth.1")]
    Man,
    /// Fit the unknown data a problem file names in its `[calibrate]` section to the values
    /// it must reproduce, then solve the design with the fitted values.
    #[command(after_help = "Example:\n  cwsynth calibrate my-calibrate.toml --out results/")]
    Calibrate {
        /// The problem file (with a `[calibrate]` section).
        file: PathBuf,
        /// Write the calibrated result (`<name>-calibrated.json`, `.md`, plots) here.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print the calibrated result's JSON instead of the summary.
        #[arg(long)]
        json: bool,
        /// Units of the written reports (Markdown, HTML): `workshop` (mm, °, rpm, kN) or `si`
        /// (as the JSON, which is always SI).
        #[arg(long, value_enum, default_value_t = UnitsArg::Workshop)]
        units: UnitsArg,
    },
    /// Serve the designer in the browser: open a problem file of DIR, edit it and see it
    /// re-solved on every edit; and the HTTP API (docs/serve.md).
    #[command(
        after_help = "Examples:\n  cwsynth serve problems/\n  cwsynth serve --port 9000 .\n  cwsynth serve --listen 0.0.0.0 --token $(openssl rand -hex 16) problems/"
    )]
    Serve {
        /// The folder whose problem files the page opens.
        #[arg(default_value = ".")]
        dir: PathBuf,
        /// The port (0: any free one).
        #[arg(long, default_value_t = 8321)]
        port: u16,
        /// Listen on this address instead of 127.0.0.1 (another machine can then reach
        /// the server: needs --token).
        #[arg(long)]
        listen: Option<std::net::IpAddr>,
        /// The token every API request must then carry (`Authorization: Bearer <token>`,
        /// at least 16 characters); the printed address carries it for the page.
        #[arg(long)]
        token: Option<String>,
        /// Seconds one solve may take before its request gets an error (the server goes on).
        #[arg(long, default_value_t = 30.0)]
        solve_budget: f64,
        /// Do not open the page in the desktop's browser (it is opened where there is one).
        #[arg(long)]
        no_open: bool,
    },
    /// Solve one scene along a ladder of accuracy and fidelity settings: time against error.
    #[command(after_help = "Example:\n  cwsynth study problems/piston-1000rpm.toml --out study/")]
    Study {
        /// The problem file.
        file: PathBuf,
        /// Write `<name>-study.csv`, `.md` and `.svg` into this directory.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Timed repeats per rung (the median is reported).
        #[arg(long, default_value_t = 5)]
        repeats: usize,
    },
}

/// The family names, for `cwsynth new` (clap lists them and suggests the nearest).
fn family_names() -> Vec<&'static str> {
    crate::families::FAMILIES.iter().map(|f| f.name()).collect()
}

/// `--units`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum UnitsArg {
    /// mm, °, rpm, kN.
    Workshop,
    /// m, rad, rad/s, N (as the JSON).
    Si,
}

impl From<UnitsArg> for crate::report::Units {
    fn from(u: UnitsArg) -> Self {
        match u {
            UnitsArg::Workshop => crate::report::Units::Workshop,
            UnitsArg::Si => crate::report::Units::Si,
        }
    }
}

/// Standard output that ends quietly when its reader goes away (`cwsynth solve --json |
/// head`): a closed pipe is not an error of ours, so the run stops writing and exits.
struct Stdout {
    out: std::io::StdoutLock<'static>,
    closed: bool,
}

impl Stdout {
    fn new() -> Self {
        Stdout {
            out: std::io::stdout().lock(),
            closed: false,
        }
    }
    /// Writes `text`; `Err` only for a real I/O error (a closed pipe sets `closed`).
    fn write(&mut self, text: &str) -> anyhow::Result<()> {
        use std::io::Write;
        if self.closed {
            return Ok(());
        }
        match self
            .out
            .write_all(text.as_bytes())
            .and_then(|_| self.out.flush())
        {
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
                self.closed = true;
                Ok(())
            }
            r => r.context("writing to standard output"),
        }
    }
}

fn summary(r: &SolveResult) -> String {
    let mut s = format!(
        "{} ({}): {}{}\n",
        r.name,
        r.family,
        r.status,
        r.status_detail
            .as_ref()
            .map(|d| format!(" ({d})"))
            .unwrap_or_default()
    );
    if let Some(e) = &r.search {
        s += &format!(
            "  search     {} starts, {} basins, {} at the best, {} evaluations (not proven optimal)\n",
            e.starts, e.distinct_basins, e.starts_at_best, e.evaluations
        );
    }
    // What to build, in the report's units (workshop: mm, °, rpm, kN), the JSON's SI key after.
    let shown = |k: &str, v: f64| {
        let (words, unit, f) = crate::report::display_unit(r.units, k, v);
        let unit = if unit == "–" { "" } else { unit };
        (words, fmt_num(v * f), unit, f)
    };
    for (k, v) in &r.design {
        let (words, num, unit, _) = shown(k, *v);
        s += &format!("  design     {words:<34} {num:>12} {unit:<6} [{k}]\n");
    }
    for (k, v) in &r.objectives {
        let (words, num, unit, f) = shown(k, *v);
        let e = r
            .errors
            .get(k)
            .map(|e| format!("± {:.1e}", e * f))
            .unwrap_or_default();
        s += &format!("  objective  {words:<34} {num:>12} {unit:<6} {e:<9} [{k}]\n");
    }
    // Each baseline in the objective its improvement is measured in (the peak force where
    // the baseline does not carry the objective's key).
    for (name, b) in &r.baselines {
        let key = r
            .objective
            .as_deref()
            .filter(|k| b.contains_key(*k))
            .unwrap_or("peak_shaking_force_n");
        if let (Some(p), Some(i)) = (b.get(key), b.get("improvement_pct")) {
            let (words, unit, f) = crate::report::workshop_unit(key, *p);
            s += &format!(
                "  baseline   {name:<34} {words} {} {unit} ({} {:+.1} %)\n",
                fmt_num(p * f),
                r.status.design_label(),
                -i
            );
        }
    }
    for c in &r.paper {
        s += &format!(
            "  paper      {}: paper {} vs {}{}\n",
            c.quantity,
            fmt_num(c.paper),
            c.computed.map(fmt_num).unwrap_or("–".into()),
            c.diff_pct
                .map(|d| format!(" ({d:+.2} %)"))
                .unwrap_or_default()
        );
    }
    for w in &r.warnings {
        s += &format!("  warning    {w}\n");
    }
    s += &format!(
        "  method     {}\n  time       {:.3} ms\n",
        r.method,
        r.timing.total_s * 1e3
    );
    s
}

/// A problem file from standard input (named `<stdin>` in messages and as the source), read
/// up to the problem-file limit.
fn load_stdin() -> Result<Scene, String> {
    use std::io::Read;
    let limit = crate::problem::MAX_FILE_BYTES;
    let mut bytes = Vec::new();
    std::io::stdin()
        .take(limit as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("<stdin>: cannot read: {e}"))?;
    families::parse_bytes(&bytes, Path::new("<stdin>")).map_err(|e| e.to_string())
}

fn load_all(files: &[PathBuf]) -> (Vec<Scene>, Vec<String>) {
    let mut ok = Vec::new();
    let mut bad = Vec::new();
    for f in files {
        match families::load(f) {
            Ok(s) => ok.push(s),
            Err(e) => bad.push(e.to_string()),
        }
    }
    (ok, bad)
}

/// The manual page (roff): clap_mangen's title, name, synopsis, description and options,
/// then every command in full in one page (clap_mangen's own subcommand section points to
/// `cwsynth-solve(1)` pages that are not installed), EXIT STATUS and EXAMPLES.
fn man_page() -> anyhow::Result<String> {
    use clap_mangen::Man;
    let cmd = Cli::command();
    let mut buf = Vec::new();
    let man = Man::new(cmd.clone());
    man.render_title(&mut buf)?;
    man.render_name_section(&mut buf)?;
    man.render_synopsis_section(&mut buf)?;
    man.render_description_section(&mut buf)?;
    man.render_options_section(&mut buf)?;
    let mut page = String::from_utf8(buf)?;
    page += ".SH COMMANDS\n";
    let mut examples = String::new();
    for sub in cmd.get_subcommands() {
        let name = format!("cwsynth {}", sub.get_name());
        let sub = sub
            .clone()
            .bin_name(name.clone())
            .display_name(name.clone());
        let mut b = Vec::new();
        let man = Man::new(sub.clone());
        man.render_synopsis_section(&mut b)?;
        man.render_options_section(&mut b)?;
        let text = String::from_utf8(b)?
            .replace(".SH SYNOPSIS\n", "")
            .replace(".SH OPTIONS\n", "");
        let about = sub.get_about().map(|a| a.to_string()).unwrap_or_default();
        page += &format!(".SS \"{name}\"\n{}\n.PP\n{text}", roff(&about));
        if let Some(after) = sub.get_after_help() {
            for line in after.to_string().lines().filter(|l| l.starts_with("  ")) {
                examples += &format!(".TP\n\\fB{}\\fR\n", roff(line.trim()));
            }
        }
    }
    page += ".SH \"EXIT STATUS\"\n\
        .TP\n0\nEvery input was read and solved, checked or written.\n\
        .TP\n1\nAn input did not load (its file, line and field are on standard error), a \
        machine failed, was infeasible or stopped on an internal error, or a result name \
        clashed; the other inputs were still solved and written.\n\
        .TP\n2\nThe command line is wrong, or the run could not go on (an output directory \
        that cannot be written).\n";
    page += &format!(".SH EXAMPLES\n{examples}");
    page += &format!(
        ".SH \"SEE ALSO\"\nThe problem files and results are documented in docs/problem-files.md and \
         docs/results.md of the source.\n.SH VERSION\nv{}\n",
        env!("CARGO_PKG_VERSION")
    );
    Ok(page)
}

/// Text as roff: backslashes and hyphens escaped, no line starting with a control character.
fn roff(text: &str) -> String {
    let t = text.replace('\\', "\\e").replace('-', "\\-");
    match t.starts_with(['.', '\'']) {
        true => format!("\\&{t}"),
        false => t,
    }
}

/// Runs the CLI; returns the process exit code. One function per verb.
pub fn run(cli: Cli) -> anyhow::Result<i32> {
    match cli.command {
        Command::Check { inputs } => check(&inputs),
        Command::Batch {
            inputs,
            out,
            quiet,
            merge: true,
            ..
        } => merge_in_place(&inputs, out, quiet),
        Command::Batch {
            inputs,
            out,
            threads,
            shard,
            quiet,
            summary_only,
            merge: false,
            units,
        } => batch(
            &inputs,
            out,
            threads.map(usize::from),
            shard,
            quiet,
            summary_only,
            units,
        ),
        Command::Merge { dirs, out } => merge(&dirs, &out, false),
        Command::Calibrate {
            file,
            out,
            json,
            units,
        } => calibrate(&file, out, json, units),
        Command::Study { file, out, repeats } => study(&file, out, repeats),
        Command::Serve {
            dir,
            port,
            listen,
            token,
            solve_budget,
            no_open,
        } => serve(dir, port, listen, token, solve_budget, !no_open),
        Command::New { family } => {
            let text = crate::families::new_problem(&family)
                .with_context(|| format!("unknown family `{family}`"))?;
            Stdout::new().write(&text)?;
            Ok(0)
        }
        Command::Completions { shell } => {
            let mut buf = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "cwsynth", &mut buf);
            Stdout::new().write(&String::from_utf8(buf)?)?;
            Ok(0)
        }
        Command::Man => {
            Stdout::new().write(&man_page()?)?;
            Ok(0)
        }
        Command::Schema => {
            Stdout::new().write(
                &(serde_json::to_string_pretty(&crate::families::problem_schema())? + "\n"),
            )?;
            Ok(0)
        }
        Command::Solve {
            inputs,
            json,
            out,
            units,
        } => solve(&inputs, json, out.as_deref(), units),
    }
}

/// `cwsynth serve`: the designer until the process is stopped.
fn serve(
    dir: PathBuf,
    port: u16,
    listen: Option<std::net::IpAddr>,
    token: Option<String>,
    solve_budget: f64,
    open: bool,
) -> anyhow::Result<i32> {
    if !(solve_budget > 0.0 && solve_budget <= 86_400.0) {
        anyhow::bail!("--solve-budget: allowed: 0 < seconds ≤ 86400");
    }
    let mut o = crate::serve::Options::new(dir);
    o.port = port;
    o.listen = listen.unwrap_or(o.listen);
    o.token = token;
    o.solve_budget = std::time::Duration::from_secs_f64(solve_budget);
    crate::serve::run(o, open)?;
    Ok(0)
}

/// `cwsynth check`: reads every file, prints `ok` for each that resolves and `error` for
/// each that does not; exit code 1 when any failed.
fn check(inputs: &[PathBuf]) -> anyhow::Result<i32> {
    let (ok, bad) = load_inputs(inputs)?;
    let mut stdout = Stdout::new();
    for s in &ok {
        stdout.write(&format!(
            "ok    {} ({}, {})\n",
            s.source.display(),
            s.name,
            s.family.name()
        ))?;
    }
    for e in &bad {
        eprintln!("error {e}");
    }
    Ok(if bad.is_empty() { 0 } else { 1 })
}

/// `cwsynth batch --merge`: joins the shard summaries in `--out` (no inputs allowed).
fn merge_in_place(inputs: &[String], out: PathBuf, quiet: bool) -> anyhow::Result<i32> {
    if !inputs.is_empty() {
        anyhow::bail!("--merge takes no inputs: it joins the shard summaries in --out");
    }
    merge(std::slice::from_ref(&out), &out, quiet)
}

/// `cwsynth batch`: solves every input into `out` (a shard of them with `--shard`) and
/// writes the summary; exit code 1 when any machine failed.
fn batch(
    inputs: &[String],
    out: PathBuf,
    threads: Option<usize>,
    shard: Option<String>,
    quiet: bool,
    summary_only: bool,
    units: UnitsArg,
) -> anyhow::Result<i32> {
    if inputs.is_empty() {
        anyhow::bail!("batch: no inputs");
    }
    let opts = crate::batch::Options {
        out: out.clone(),
        threads,
        shard: shard
            .as_deref()
            .map(crate::batch::parse_shard)
            .transpose()?,
        quiet,
        summary_only,
        units: units.into(),
    };
    let c = crate::batch::run(crate::batch::expand(inputs)?, &opts)?;
    if !quiet {
        eprintln!(
            "batch: {} machines, {} ok, {} failed, {} skipped (unchanged); summary in {}",
            c.total,
            c.ok,
            c.failed,
            c.skipped,
            out.join(crate::batch::summary_name(opts.shard)).display()
        );
    }
    Ok(if c.failed > 0 { 1 } else { 0 })
}

/// `cwsynth merge` (and `batch --merge`): joins the summaries of the shard directories
/// `dirs` into `out`, saying so unless `quiet`; exit code 1 when any machine failed.
fn merge(dirs: &[PathBuf], out: &Path, quiet: bool) -> anyhow::Result<i32> {
    let c = crate::batch::merge(dirs, out)?;
    if !quiet {
        eprintln!(
            "merged {} machines ({} failed) into {}",
            c.total,
            c.failed,
            out.join("summary.csv").display()
        );
    }
    Ok(if c.failed > 0 { 1 } else { 0 })
}

/// `cwsynth calibrate`: fits the file's parameters, prints the fit (or its JSON) and the
/// calibrated result's summary, and writes the result into `out` when given.
fn calibrate(
    file: &Path,
    out: Option<PathBuf>,
    json: bool,
    units: UnitsArg,
) -> anyhow::Result<i32> {
    let text =
        std::fs::read_to_string(file).with_context(|| format!("cannot read {}", file.display()))?;
    let mut c = crate::calibrate::calibrate(&text, file)?;
    let mut o = Stdout::new();
    if json {
        o.write(&(serde_json::to_string_pretty(&c.result.to_json())? + "\n"))?;
    } else {
        o.write(&fit_text(file, &c.fit))?;
        o.write(&summary(&c.result))?;
    }
    if let Some(dir) = out {
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        c.result.units = units.into();
        write_outputs(&mut c.result, &dir)
            .with_context(|| format!("writing into {}", dir.display()))?;
    }
    Ok(if c.result.status == Status::Failed {
        1
    } else {
        0
    })
}

/// The calibration's text: method, solves and χ², each parameter with its 1σ uncertainty
/// (or "not identifiable"), each matched value against its target, and the notes.
fn fit_text(file: &Path, f: &crate::calibrate::Fit) -> String {
    let mut t = format!(
        "{}: calibration ({}; {} solves), χ² = {:.3e}\n",
        file.display(),
        f.method,
        f.evaluations,
        f.chi2
    );
    for p in &f.parameters {
        t += &format!(
            "  {} = {} {}{}\n",
            p.key,
            fmt_num(p.value),
            p.unit,
            match p.uncertainty {
                Some(u) => format!(" ± {} {} (1σ)", fmt_num(u), p.unit),
                None => " (not identifiable)".into(),
            }
        );
    }
    for m in &f.matches {
        t += &format!(
            "  {}: {} against {} (residual {:.3e}, σ {:.3e})\n",
            m.key,
            fmt_num(m.fitted),
            fmt_num(m.target),
            m.residual,
            m.sigma
        );
    }
    for n in &f.notes {
        t += &format!("  note: {n}\n");
    }
    t
}

/// `cwsynth study`: runs the study file (`repeats` timings, at least 1), prints its
/// Markdown and writes its CSV, Markdown and SVG into `out` when given.
fn study(file: &Path, out: Option<PathBuf>, repeats: usize) -> anyhow::Result<i32> {
    let text =
        std::fs::read_to_string(file).with_context(|| format!("cannot read {}", file.display()))?;
    let st = crate::study::study(&text, file, repeats.max(1))?;
    let md = crate::study::markdown(&st);
    Stdout::new().write(&md)?;
    if let Some(dir) = out {
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        let svg = crate::study::svg(&st)?;
        for (ext, body) in [("csv", crate::study::csv(&st)), ("md", md), ("svg", svg)] {
            let p = dir.join(format!("{}-study.{ext}", st.name));
            crate::report::write_atomic(&p, body.as_bytes())
                .with_context(|| format!("writing {}", p.display()))?;
        }
    }
    Ok(0)
}

/// Reads the scenes of `inputs` (files, directories, `-` for standard input, read first):
/// (the scenes, the errors of those that did not load).
fn load_inputs(inputs: &[PathBuf]) -> anyhow::Result<(Vec<Scene>, Vec<String>)> {
    let stdin = inputs.iter().any(|p| p.as_os_str() == "-");
    let paths: Vec<PathBuf> = inputs
        .iter()
        .filter(|p| p.as_os_str() != "-")
        .cloned()
        .collect();
    let files = crate::batch::expand_inputs(&paths)?;
    let (mut scenes, mut bad) = load_all(&files);
    if stdin {
        match load_stdin() {
            Ok(s) => scenes.insert(0, s),
            Err(e) => bad.insert(0, e),
        }
    }
    Ok((scenes, bad))
}

/// `cwsynth solve`: solves each file, prints its summary (or JSON line) and writes its
/// results into `out` when given; exit code 1 when a file did not load, a name clashed, a
/// scene panicked, failed or was infeasible.
fn solve(
    inputs: &[PathBuf],
    json: bool,
    out: Option<&Path>,
    units: UnitsArg,
) -> anyhow::Result<i32> {
    let (scenes, bad) = load_inputs(inputs)?;
    for e in &bad {
        eprintln!("error {e}");
    }
    let mut failed = !bad.is_empty();
    let mut stdout = Stdout::new();
    // With --out, two scenes whose file names clash (same name, or names equal but
    // for case, which clash on case-insensitive file systems) would overwrite each
    // other: the first keeps it, the later one is an error.
    let mut taken: std::collections::BTreeMap<String, &Path> = Default::default();
    for sc in &scenes {
        if out.is_some() {
            if let Some(first) = taken.get(&sc.name.to_lowercase()) {
                eprintln!(
                    "error {}: name `{}` clashes with {} (result files would overwrite each other); give it another `name`",
                    sc.source.display(),
                    sc.name,
                    first.display()
                );
                failed = true;
                continue;
            }
            taken.insert(sc.name.to_lowercase(), &sc.source);
        }
        let Some(r) = solve_isolated(sc, units, out)? else {
            failed = true;
            continue;
        };
        failed |= matches!(r.status, Status::Failed | Status::Infeasible);
        if json {
            stdout.write(&(serde_json::to_string(&r.to_json())? + "\n"))?;
        } else {
            stdout.write(&summary(&r))?;
        }
    }
    Ok(if failed { 1 } else { 0 })
}

/// Solves one scene and writes its results into `out` when given, isolated: a panic fails
/// that scene only (reported once, on stderr, and `None`); a write error ends the run.
fn solve_isolated(
    sc: &Scene,
    units: UnitsArg,
    out: Option<&Path>,
) -> anyhow::Result<Option<SolveResult>> {
    match crate::batch::isolate(|| {
        crate::batch::test_panic(&sc.name);
        let mut r = solve_scene(sc);
        r.units = units.into();
        let written = out.map(|dir| write_outputs(&mut r, dir));
        (r, written)
    }) {
        Ok((r, written)) => {
            if let Some(Err(e)) = written {
                return Err(e).with_context(|| format!("writing results of {}", r.name));
            }
            Ok(Some(r))
        }
        Err(panic) => {
            eprintln!(
                "error {}: internal error (a panic, please report it): {panic}",
                sc.source.display()
            );
            Ok(None)
        }
    }
}

/// Entry point used by `main.rs`.
pub fn main() -> i32 {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("cwsynth: {e:#}");
            2
        }
    }
}
