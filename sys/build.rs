//! Generates the PETSc bindings with bindgen against Debian's PETSc 3.18, found by pkg-config,
//! and compiles the small C shim for what bindgen cannot translate (MPI handles and macros).
use std::env;
use std::path::{Path, PathBuf};

const INSTALL_HINT: &str = "install it with:\n    sudo apt-get install -y --no-install-recommends \
     libpetsc-real3.18-dev libclang-dev pkg-config openmpi-bin\n(or run ./setup.sh from the signorini checkout)";

fn fail(what: &str) -> ! {
    eprintln!("\nerror: signorini-sys: {what}\n{INSTALL_HINT}\n");
    panic!("signorini-sys: {what}; {INSTALL_HINT}");
}

fn libclang_present() -> bool {
    if let Ok(dir) = env::var("LIBCLANG_PATH") {
        if Path::new(&dir).exists() {
            return true;
        }
    }
    let roots = ["/usr/lib", "/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/local/lib"];
    let has_lib = |dir: &Path| {
        std::fs::read_dir(dir)
            .map(|entries| {
                entries.flatten().any(|e| {
                    e.file_name().to_string_lossy().starts_with("libclang")
                        && e.file_name().to_string_lossy().contains(".so")
                })
            })
            .unwrap_or(false)
    };
    if roots.iter().any(|r| has_lib(Path::new(r))) {
        return true;
    }
    // Debian keeps libclang under /usr/lib/llvm-N/lib.
    std::fs::read_dir("/usr/lib")
        .map(|entries| {
            entries
                .flatten()
                .filter(|e| e.file_name().to_string_lossy().starts_with("llvm-"))
                .any(|e| has_lib(&e.path().join("lib")))
        })
        .unwrap_or(false)
}

fn main() {
    println!("cargo:rerun-if-changed=wrapper.h");
    println!("cargo:rerun-if-changed=shim.h");
    println!("cargo:rerun-if-changed=shim.c");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");

    let petsc = match pkg_config::Config::new().atleast_version("3.18").probe("PETSc") {
        Ok(lib) => lib,
        Err(e) => fail(&format!("PETSc >= 3.18 was not found by pkg-config ({e})")),
    };
    // The shim calls MPI directly, so link libmpi too (pkg-config emits the link flags).
    let mpi_includes: Vec<PathBuf> = match pkg_config::Config::new().probe("mpi") {
        Ok(lib) => lib.include_paths,
        Err(_) => {
            // Fall back on mpicc's own view of its include dirs.
            match std::process::Command::new("mpicc").arg("-showme:incdirs").output() {
                Ok(out) if out.status.success() => {
                    println!("cargo:rustc-link-lib=mpi");
                    String::from_utf8_lossy(&out.stdout).split_whitespace().map(PathBuf::from).collect()
                }
                _ => fail("the MPI headers were not found (neither pkg-config 'mpi' nor mpicc)"),
            }
        }
    };
    if !libclang_present() {
        fail("libclang (needed by bindgen to read the PETSc headers) was not found");
    }

    let include_paths: Vec<PathBuf> = petsc.include_paths.iter().chain(mpi_includes.iter()).cloned().collect();

    let mut shim = cc::Build::new();
    shim.file("shim.c").warnings(false);
    for p in &include_paths {
        shim.include(p);
    }
    shim.compile("signorini_shim");

    let mut builder = bindgen::Builder::default()
        .header("wrapper.h")
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()))
        .default_enum_style(bindgen::EnumVariation::NewType { is_bitfield: false, is_global: false })
        .allowlist_function("(Petsc|Vec|Mat|KSP|PC|SNES|Tao|IS|ISLocalToGlobal|DM)[A-Za-z0-9_]*")
        .allowlist_function("signorini_[a-z0-9_]*")
        .allowlist_type("(Petsc|Vec|Mat|KSP|PC|SNES|Tao|IS|ISLocalToGlobal|DM|_p_)[A-Za-z0-9_]*")
        .allowlist_type("MPI_Comm|InsertMode|NormType|ScatterMode")
        .allowlist_var("(PETSC|KSP|PC|SNES|TAO|MAT|VEC|NORM|INSERT|ADD)_[A-Za-z0-9_]*")
        .allowlist_var("(Petsc|PETSC_COMM|KSP|SNES|Tao|PC)[A-Za-z0-9_]*")
        .layout_tests(false)
        .derive_default(true);
    for p in &include_paths {
        builder = builder.clang_arg(format!("-I{}", p.display()));
    }
    let bindings = match builder.generate() {
        Ok(b) => b,
        Err(e) => fail(&format!("bindgen could not read the PETSc headers ({e})")),
    };
    let out = PathBuf::from(env::var("OUT_DIR").unwrap()).join("bindings.rs");
    bindings.write_to_file(&out).expect("write bindings.rs");
}
