//! Output bits that depend on nothing the host supplies: the binary takes no maths from the
//! C library (src/pure_maths.rs defines every such symbol from the pure-Rust `libm`), so two
//! farm hosts with different glibc versions render the same frames. The golden table
//! (golden.rs) pins the bits themselves.

use std::process::Command;

use crate::common;

/// The C library's inexact maths functions (f64 name; the f32 one adds `f`): any of them
/// imported would let the host's last bit into a frame.
const MATHS: &[&str] = &[
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "asinh", "acosh",
    "atanh", "exp", "exp2", "exp10", "expm1", "log", "log2", "log10", "log1p", "pow", "cbrt",
    "hypot", "sincos", "erf", "erfc", "tgamma", "lgamma", "lgamma_r",
];

#[test]
fn the_binary_takes_no_maths_from_the_host() {
    if !common::require_tools(common::this_test!(), &["nm"], "apt-get install binutils") {
        return;
    }
    let o = Command::new("nm")
        .args(["-D", "--undefined-only"])
        .arg(env!("CARGO_BIN_EXE_envshadow"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let imports = String::from_utf8_lossy(&o.stdout);
    // A dynamically linked binary imports from the C library: an empty list would mean the
    // check read nothing.
    assert!(imports.contains("malloc"), "no imports read: {imports}");
    let from_host: Vec<&str> = imports
        .lines()
        .filter_map(|l| l.split_whitespace().last())
        .map(|s| s.split('@').next().unwrap_or(s))
        .filter(|s| {
            MATHS.iter().any(|m| {
                *s == *m
                    || s.strip_suffix('f') == Some(*m)
                    || s.strip_suffix("f_r") == Some(m.trim_end_matches("_r"))
            })
        })
        .collect();
    assert!(
        from_host.is_empty(),
        "the binary calls the host's maths {from_host:?}: define them in src/pure_maths.rs, or call libm"
    );
}
