// mimalloc: a solve allocates many small, short-lived buffers; with glibc's malloc a fleet of
// 100 000 machines takes 2.41–2.46 s, with mimalloc 2.11–2.18 s. Its v2 line (Cargo feature
// "v2"): v3 reserves a 1 GiB huge-page arena at start-up and costs 0.94 ms of CPU for
// `cwsynth --version` against v2's 0.85 ms and glibc's 0.82 ms (docs/performance.md).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    std::process::exit(cwsynth::cli::main());
}
