//! Generates the C API bindings of gmsh and of PETSc and links `libgmsh`. gmsh's header is
//! `$GMSH_HEADER`, by default Debian's `/usr/include/gmshc.h`. PETSc's include and library
//! paths come from `pkg-config PETSc mpi` (Debian's libpetsc-real-dev and Open MPI); PETSc is
//! not linked but loaded when the iterative solver first runs (src/solve/petsc), from the
//! library whose path `PETSC_LIBRARY` gives the crate: loading it starts the threads of its
//! BLAS, which must inherit the signal mask that `main` sets first.

use std::path::PathBuf;
use std::process::Command;

fn main() {
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR is set by cargo"));
    println!("cargo:rerun-if-changed=build.rs");
    gmsh(&out);
    petsc(&out);
}

fn gmsh(out: &std::path::Path) {
    let header = std::env::var("GMSH_HEADER").unwrap_or_else(|_| "/usr/include/gmshc.h".into());
    println!("cargo:rerun-if-env-changed=GMSH_HEADER");
    println!("cargo:rerun-if-changed={header}");
    println!("cargo:rustc-link-lib=gmsh");
    bindgen::Builder::default()
        .header(&header)
        .allowlist_function("gmsh.*")
        .generate()
        .unwrap_or_else(|e| panic!("cannot generate gmsh bindings from {header} (set GMSH_HEADER): {e}"))
        .write_to_file(out.join("gmsh_bindings.rs"))
        .expect("cannot write gmsh bindings");
}

/// `pkg-config <flag> PETSc mpi`, split into words.
fn pkg_config(flag: &str) -> Vec<String> {
    let output = Command::new("pkg-config").args([flag, "PETSc", "mpi"]).output();
    match output {
        Ok(o) if o.status.success() => {
            String::from_utf8_lossy(&o.stdout).split_whitespace().map(String::from).collect()
        }
        _ => panic!("pkg-config {flag} PETSc mpi failed: install Debian's libpetsc-real-dev (make deps does)"),
    }
}

fn petsc(out: &std::path::Path) {
    let libs = pkg_config("--libs");
    let dir = libs.iter().find_map(|w| w.strip_prefix("-L")).expect("pkg-config gives PETSc's library directory");
    let name = libs.iter().find_map(|w| w.strip_prefix("-l").filter(|l| l.starts_with("petsc"))).expect("a -lpetsc…");
    println!("cargo:rustc-env=PETSC_LIBRARY={dir}/lib{name}.so");
    let includes = pkg_config("--cflags").into_iter().filter(|w| w.starts_with("-I"));
    bindgen::Builder::default()
        .header_contents("petsc_wrapper.h", "#include <petscksp.h>\n")
        .clang_args(includes)
        .allowlist_function("PetscInitialize|PetscInitialized|PetscPushErrorHandler|PetscReturnErrorHandler")
        .allowlist_function("PetscOptions(SetValue|HasName|ClearValue)|PetscErrorMessage")
        .allowlist_function("Mat(Create|SetSizes|SetType|SetBlockSize|SeqAIJSetPreallocationCSR|MPIAIJSetPreallocationCSR|SetNearNullSpace|Destroy)")
        .allowlist_function("MatNullSpace(CreateRigidBody|Destroy)")
        .allowlist_function("Vec(CreateMPIWithArray|Destroy)")
        .allowlist_function("KSP(Create|SetOperators|SetType|GetPC|SetTolerances|SetFromOptions|Solve|GetIterationNumber|GetConvergedReason|GetResidualNorm|Destroy)")
        .allowlist_function("PCSetType")
        .allowlist_function("MPI_(Comm_set_errhandler|Comm_spawn|Comm_get_parent|Intercomm_merge|Comm_rank|Comm_size|Bcast|Send|Recv)")
        .allowlist_type("ompi_predefined_(communicator|datatype|info|errhandler)_t")
        .dynamic_library_name("Petsc")
        .dynamic_link_require_all(true)
        .generate()
        .unwrap_or_else(|e| panic!("cannot generate PETSc bindings: {e}"))
        .write_to_file(out.join("petsc_bindings.rs"))
        .expect("cannot write PETSc bindings");
}
