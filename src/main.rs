fn main() {
    if std::env::args_os().nth(1).is_some_and(|a| a == damfem::solve::petsc::WORKER_FLAG) {
        std::process::exit(damfem::solve::petsc::serve());
    }
    damfem::cli::interrupt::install();
    // After the signal mask is set: the thread pool starts here.
    if let Ok(program) = std::env::current_exe() {
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        damfem::solve::petsc::set_workers(program, rayon::current_num_threads().min(cores) - 1);
    }
    std::process::exit(damfem::cli::run(std::env::args_os()));
}
