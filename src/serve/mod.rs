//! `cwsynth serve` (issue 35): the designer in the browser and the HTTP API it uses, a local
//! web server inside the binary (axum on tokio). Why a server at all: the page re-solves the
//! certified optimum on every edit, and the solver is this crate; the page and its scripts
//! are served by the binary (no CDN), so it works offline.
//!
//! Security (docs/serve.md): bound to 127.0.0.1 unless `--listen` names another address,
//! which needs a token every API request carries; the client names files only by their
//! bare names inside `DIR`; request bodies, solve times and concurrent solves are bounded;
//! every answer carries a Content-Security-Policy that allows only the binary's own scripts.
//! One bad request is its own JSON error and never stops the server.

mod api;
mod assets;
pub mod edit;
pub mod export;
mod listen;

use axum::Router;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

/// The server's settings (`cwsynth serve`'s options).
#[derive(Debug, Clone)]
pub struct Options {
    /// The folder whose problem files the page opens (the current directory by default).
    pub dir: PathBuf,
    /// The address to listen on: 127.0.0.1 unless asked.
    pub listen: IpAddr,
    /// The port (0: any free one).
    pub port: u16,
    /// The token every API request must carry (`Authorization: Bearer <token>`); required
    /// when `listen` is not a loopback address.
    pub token: Option<String>,
    /// The most bytes of a request body.
    pub max_body: usize,
    /// The longest a client may take to send its request body.
    pub body_time: Duration,
    /// The longest one solve may take before its request gets a JSON error.
    pub solve_budget: Duration,
    /// Solves run at once (the others wait their turn): the core count by default.
    pub max_solves: usize,
    /// The longest a client may take to send a request's head (its line and headers); the
    /// connection is closed after it.
    pub header_time: Duration,
    /// Connections open at once; one more is closed as soon as it is accepted.
    pub max_connections: usize,
}

impl Options {
    /// The defaults for `dir`: 127.0.0.1, port 8321, no token, a body of at most the
    /// problem-file limit sent within 10 s, 30 s per solve, one solve per core, a request
    /// head within 10 s, 256 connections.
    pub fn new(dir: PathBuf) -> Options {
        Options {
            dir,
            listen: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port: 8321,
            token: None,
            max_body: crate::problem::MAX_FILE_BYTES,
            body_time: Duration::from_secs(10),
            solve_budget: Duration::from_secs(30),
            max_solves: std::thread::available_parallelism().map_or(2, |n| n.get()),
            header_time: Duration::from_secs(10),
            max_connections: 256,
        }
    }

    /// Checks the settings: a folder that exists, a token where the address is not a
    /// loopback one (and then at least 16 characters), positive limits.
    pub fn validate(&self) -> Result<(), ServeError> {
        if !self.dir.is_dir() {
            return Err(ServeError::Options(format!(
                "{}: not a folder; allowed: a folder of problem files",
                self.dir.display()
            )));
        }
        match (&self.token, self.listen.is_loopback()) {
            (None, false) => {
                return Err(ServeError::Options(format!(
                    "--listen {} is not a loopback address: it needs --token (at least 16 characters) that every API request then carries",
                    self.listen
                )))
            }
            (Some(t), _) if t.chars().count() < 16 => {
                return Err(ServeError::Options(
                    "--token: at least 16 characters".into(),
                ))
            }
            _ => {}
        }
        let zero = self.solve_budget.is_zero() || self.body_time.is_zero();
        let zero = zero || self.header_time.is_zero() || self.max_connections == 0;
        if self.max_body == 0 || self.max_solves == 0 || zero {
            return Err(ServeError::Options(
                "the body limit and time, the head time, the solve budget, the solves and the connections at once must be positive"
                    .into(),
            ));
        }
        Ok(())
    }
}

/// Why the server could not start or stopped.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The settings are wrong.
    #[error("{0}")]
    Options(String),
    /// The address cannot be bound or the server failed.
    #[error("{what}: {source}")]
    Io {
        /// What was being done.
        what: String,
        /// The error.
        source: std::io::Error,
    },
}

/// The shared state of every request.
#[derive(Debug)]
pub(crate) struct State {
    pub(crate) opts: Options,
    /// The folder, canonical: a file's canonical path must start with it.
    pub(crate) root: PathBuf,
    /// One permit per solve running.
    pub(crate) solves: Arc<tokio::sync::Semaphore>,
}

/// The designer's routes on the settings `opts` (validated first).
pub fn router(opts: Options) -> Result<Router, ServeError> {
    opts.validate()?;
    let root = opts.dir.canonicalize().map_err(|source| ServeError::Io {
        what: format!("{}", opts.dir.display()),
        source,
    })?;
    let state = Arc::new(State {
        solves: Arc::new(tokio::sync::Semaphore::new(opts.max_solves)),
        root,
        opts,
    });
    Ok(api::routes(state))
}

/// Binds `opts`' address: the listener, ready to serve, and the page's routes.
fn bind(opts: Options) -> Result<Bound, ServeError> {
    let addr = SocketAddr::new(opts.listen, opts.port);
    let limits = (opts.header_time, opts.max_connections);
    let app = router(opts)?;
    let listener = std::net::TcpListener::bind(addr).map_err(|source| ServeError::Io {
        what: format!("binding {addr}"),
        source,
    })?;
    listener
        .set_nonblocking(true)
        .map_err(|source| ServeError::Io {
            what: "setting up the listener".into(),
            source,
        })?;
    Ok(Bound {
        listener,
        app,
        limits,
    })
}

/// A bound listener with the routes it serves and its connection limits (the head time,
/// the connections at once).
struct Bound {
    listener: std::net::TcpListener,
    app: Router,
    limits: (Duration, usize),
}

impl Bound {
    /// The address it listens on (the port chosen where 0 was asked).
    fn addr(&self) -> Result<SocketAddr, ServeError> {
        self.listener.local_addr().map_err(|source| ServeError::Io {
            what: "reading the bound address".into(),
            source,
        })
    }
}

/// Serves `app` on `listener` in a new runtime until it fails or the process ends.
fn serve_on(bound: Bound) -> Result<(), ServeError> {
    let Bound {
        listener,
        app,
        limits: (header_time, max_connections),
    } = bound;
    let io = |what: &str| {
        let what = what.to_string();
        move |source| ServeError::Io { what, source }
    };
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(io("starting the runtime"))?;
    rt.block_on(async move {
        let listener = tokio::net::TcpListener::from_std(listener).map_err(io("listening"))?;
        listen::accept(listener, app, header_time, max_connections)
            .await
            .map_err(io("serving"))
    })
}

/// Serves until the process ends: binds, prints the page's address (with the token, in the
/// fragment, where there is one: it never reaches a server log), and answers.
pub fn run(opts: Options, open: bool) -> Result<(), ServeError> {
    let token = opts.token.clone();
    let bound = bind(opts)?;
    let addr = bound.addr()?;
    let fragment = token.map(|t| format!("#token={t}")).unwrap_or_default();
    let url = format!("http://{addr}/{fragment}");
    println!("cwsynth serve: {url}");
    if open {
        open_browser(&url);
    }
    serve_on(bound)
}

/// Opens `url` in the desktop's browser where there is a desktop (`open` on macOS,
/// `xdg-open` where `DISPLAY` or `WAYLAND_DISPLAY` is set); quietly nothing otherwise (a
/// server, a container, CI): the printed address is the way in.
fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        Some("open")
    } else if std::env::var_os("DISPLAY").is_some() || std::env::var_os("WAYLAND_DISPLAY").is_some()
    {
        Some("xdg-open")
    } else {
        None
    };
    if let Some(cmd) = opener {
        let _ = std::process::Command::new(cmd)
            .arg(url)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn();
    }
}

/// A server on a background thread (tests, embedding): it answers at `addr` until the
/// process ends.
pub fn start(opts: Options) -> Result<SocketAddr, ServeError> {
    let bound = bind(opts)?;
    let addr = bound.addr()?;
    std::thread::spawn(move || serve_on(bound));
    Ok(addr)
}
