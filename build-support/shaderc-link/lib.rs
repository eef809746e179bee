//! Link-only crate: its build script adds native libraries (see build.rs).
