fn main() {
    std::process::exit(damfem::cli::run(std::env::args_os()));
}
