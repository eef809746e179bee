//! Completes Debian's `libshaderc_combined.a`, which holds only shaderc's own
//! objects, with the glslang and SPIRV-Tools static libraries it needs.
//! Prints nothing (so shaderc-sys's own search stands) when `SHADERC_LIB_DIR`
//! or `VULKAN_SDK` is set or when those libraries are absent.
use std::env;
use std::path::Path;

/// Dependency order for a single-pass static link: users before providers.
const GLSLANG_AND_SPIRV_TOOLS: &[&str] = &[
    "glslang",
    "MachineIndependent",
    "OSDependent",
    "GenericCodeGen",
    "OGLCompiler",
    "SPIRV",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

fn main() {
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    println!("cargo:rerun-if-env-changed=VULKAN_SDK");
    if env::var_os("SHADERC_LIB_DIR").is_some() || env::var_os("VULKAN_SDK").is_some() {
        return;
    }
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        return;
    }
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let dir = format!("/usr/lib/{arch}-linux-gnu");
    let has = |lib: &str| Path::new(&dir).join(format!("lib{lib}.a")).is_file();
    if !has("shaderc_combined") || !GLSLANG_AND_SPIRV_TOOLS.iter().all(|lib| has(lib)) {
        return;
    }
    println!("cargo:rustc-link-search=native={dir}");
    println!("cargo:rustc-link-lib=static=shaderc_combined");
    for lib in GLSLANG_AND_SPIRV_TOOLS {
        println!("cargo:rustc-link-lib=static={lib}");
    }
    println!("cargo:rustc-link-lib=dylib=stdc++");
}
