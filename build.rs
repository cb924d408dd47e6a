//! Generates the C API bindings of gmsh and of PETSc and links `libgmsh`, `libpetsc_real` and
//! MPI. gmsh's header is `$GMSH_HEADER`, by default Debian's `/usr/include/gmshc.h`; PETSc's
//! include and library paths come from `pkg-config PETSc mpi` (Debian's libpetsc-real-dev and
//! Open MPI).

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
    for word in pkg_config("--libs") {
        if let Some(dir) = word.strip_prefix("-L") {
            println!("cargo:rustc-link-search=native={dir}");
        } else if let Some(lib) = word.strip_prefix("-l") {
            println!("cargo:rustc-link-lib={lib}");
        }
    }
    let includes = pkg_config("--cflags").into_iter().filter(|w| w.starts_with("-I"));
    bindgen::Builder::default()
        .header_contents("petsc_wrapper.h", "#include <petscksp.h>\n")
        .clang_args(includes)
        .allowlist_function("PetscInitialize|PetscInitialized|PetscPushErrorHandler|PetscReturnErrorHandler")
        .allowlist_function("PetscOptionsSetValue|PetscErrorMessage")
        .allowlist_function("Mat(Create|SetSizes|SetType|SetBlockSize|SeqAIJSetPreallocationCSR|SetNearNullSpace|Destroy)")
        .allowlist_function("MatNullSpace(CreateRigidBody|Destroy)")
        .allowlist_function("Vec(CreateSeqWithArray|SetBlockSize|Destroy)")
        .allowlist_function("KSP(Create|SetOperators|SetType|GetPC|SetTolerances|SetFromOptions|Solve|GetIterationNumber|GetConvergedReason|GetResidualNorm|Destroy)")
        .allowlist_function("PCSetType")
        .allowlist_var("ompi_mpi_comm_self")
        .generate()
        .unwrap_or_else(|e| panic!("cannot generate PETSc bindings: {e}"))
        .write_to_file(out.join("petsc_bindings.rs"))
        .expect("cannot write PETSc bindings");
}
