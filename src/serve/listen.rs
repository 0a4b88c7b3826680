//! The server's accept loop, written here instead of `axum::serve` because that one gives
//! hyper no timer, so hyper's header-read timeout never fires and a client that sends its
//! request head a byte at a time (a "slowloris") holds its connection for ever. Here every
//! connection is hyper's HTTP/1 with a Tokio timer: its head must arrive within
//! [`super::Options::header_time`], and at most [`super::Options::max_connections`] are
//! open at once (a new one over the limit is closed at once, the open ones keep being
//! served). A failed connection is that connection's end, never the server's.

use axum::Router;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use std::sync::Arc;
use std::time::Duration;

/// Accepts connections on `listener` and serves `app` on each until the process ends.
pub(super) async fn accept(
    listener: tokio::net::TcpListener,
    app: Router,
    header_time: Duration,
    max_connections: usize,
) -> std::io::Result<()> {
    let open = Arc::new(tokio::sync::Semaphore::new(max_connections));
    loop {
        let stream = match listener.accept().await {
            Ok((stream, _)) => stream,
            // Out of descriptors or a connection reset before it was accepted: wait a little
            // and go on (what axum::serve does too).
            Err(_) => {
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            }
        };
        // Answers go out as soon as they are written (no Nagle delay on a small last
        // segment).
        let _ = stream.set_nodelay(true);
        let Ok(permit) = open.clone().try_acquire_owned() else {
            drop(stream);
            continue;
        };
        let service = TowerToHyperService::new(app.clone());
        tokio::spawn(async move {
            let _permit = permit;
            let mut http = hyper::server::conn::http1::Builder::new();
            http.timer(TokioTimer::new())
                .header_read_timeout(header_time);
            // The connection's own error (a reset, a timeout, a malformed head) ends it only.
            let _ = http.serve_connection(TokioIo::new(stream), service).await;
        });
    }
}
