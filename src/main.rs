fn main() {
    damfem::cli::interrupt::install();
    std::process::exit(damfem::cli::run(std::env::args_os()));
}
