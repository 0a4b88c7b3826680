fn main() {
    std::process::exit(cwsynth::cli::main());
}
