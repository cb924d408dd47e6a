//! Generates the gmsh C API bindings and links `libgmsh`. The header is `$GMSH_HEADER`, by
//! default Debian's `/usr/include/gmshc.h`.

fn main() {
    let header = std::env::var("GMSH_HEADER").unwrap_or_else(|_| "/usr/include/gmshc.h".into());
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=GMSH_HEADER");
    println!("cargo:rerun-if-changed={header}");
    println!("cargo:rustc-link-lib=gmsh");
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR is set by cargo"));
    bindgen::Builder::default()
        .header(&header)
        .allowlist_function("gmsh.*")
        .generate()
        .unwrap_or_else(|e| panic!("cannot generate gmsh bindings from {header} (set GMSH_HEADER): {e}"))
        .write_to_file(out.join("gmsh_bindings.rs"))
        .expect("cannot write gmsh bindings");
}
