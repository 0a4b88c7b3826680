//! One machine cannot take the others down: its whole pipeline runs under
//! `catch_unwind`, and a panic becomes that machine's reason instead of the run's end
//! (`cwsynth solve` uses the same for each file).

use super::row::MESSAGE_BYTES;
use crate::report::truncate;

thread_local! {
    /// Set while [`isolate`] runs on this thread: the panic hook records instead of printing.
    static CATCHING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// The last panic [`isolate`] caught on this thread: message and location.
    static CAUGHT: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Runs `f`; a panic inside it is returned as `Err("message at file:line")` instead of
/// unwinding further, and the default hook's report on stderr is replaced by that value
/// (the caller reports it once, as the machine's reason). Panics on other threads, or
/// outside `isolate`, are reported by the previous hook as before. This is how one machine
/// of a batch (or one file of `cwsynth solve`) cannot take the others down: whatever its
/// parse, solve, report or plot does, the run finishes and says why that machine failed.
/// (An abort, e.g. an allocation failure, cannot be caught; input limits prevent those.)
pub fn isolate<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if CATCHING.with(|c| c.get()) {
                let at = info
                    .location()
                    .map(|l| format!(" at {}:{}", l.file(), l.line()))
                    .unwrap_or_default();
                let message = panic_message(info.payload());
                CAUGHT.with(|c| *c.borrow_mut() = Some(format!("{message}{at}")));
            } else {
                previous(info)
            }
        }));
    });
    let was = CATCHING.with(|c| c.replace(true));
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    CATCHING.with(|c| c.set(was));
    r.map_err(|payload| {
        CAUGHT
            .with(|c| c.borrow_mut().take())
            .unwrap_or_else(|| panic_message(&*payload))
    })
}

/// The text of a panic's payload (`panic!("…")` gives a `&str` or a `String`).
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    let m = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)");
    truncate(m, MESSAGE_BYTES).into_owned()
}

/// A debugging and test hook of debug builds only: `CWSYNTH_TEST_PANIC=NAME` makes the
/// machine named `NAME` panic just before it is solved (`cwsynth batch` and `cwsynth solve`),
/// to show that one machine's panic fails that machine only (`tests/batch.rs`). Release
/// builds ignore the variable.
pub fn test_panic(name: &str) {
    if cfg!(debug_assertions) && std::env::var_os("CWSYNTH_TEST_PANIC").is_some_and(|n| n == name) {
        panic!("CWSYNTH_TEST_PANIC: a test panic in machine `{name}`");
    }
}
