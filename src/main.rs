// mimalloc: a solve allocates many small, short-lived buffers; glibc's malloc took ~10 % of
// a fleet run's time (perf), mimalloc about a third of that.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    std::process::exit(cwsynth::cli::main());
}
