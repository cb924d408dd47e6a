//! Generates the gmsh C API bindings (`/usr/include/gmshc.h`) and links `libgmsh`.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rustc-link-lib=gmsh");
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR is set by cargo"));
    bindgen::Builder::default()
        .header("/usr/include/gmshc.h")
        .allowlist_function("gmsh.*")
        .generate()
        .expect("cannot generate gmsh bindings from /usr/include/gmshc.h")
        .write_to_file(out.join("gmsh_bindings.rs"))
        .expect("cannot write gmsh bindings");
}
