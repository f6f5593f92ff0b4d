//! The C maths functions this executable links, defined here from the pure-Rust `libm` crate.
//!
//! Rust's `f32::sin` and friends, and the crates we depend on (the EXR decoder's DWA transfer
//! curve, image resampling, progress estimates), call the C library's `sinf`, `powf`, … whose
//! last bit differs between glibc versions: two farm hosts on different distributions could
//! render different frames. Defined in the executable, these symbols satisfy every such call
//! at link time, so the binary imports no maths from the host (`nm -D` lists none; the test
//! `maths::the_binary_takes_no_maths_from_the_host` checks it) and its output bits are the same
//! on every host. The library's own code calls `libm` directly, so in-process uses agree too.

use std::ffi::{c_double, c_float, c_int};

macro_rules! unary {
    ($($name:ident: $t:ty;)*) => {$(
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: $t) -> $t {
            libm::$name(x)
        }
    )*};
}

macro_rules! binary {
    ($($name:ident: $t:ty;)*) => {$(
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(x: $t, y: $t) -> $t {
            libm::$name(x, y)
        }
    )*};
}

unary! {
    sinf: c_float; cosf: c_float; tanf: c_float; asinf: c_float; acosf: c_float;
    atanf: c_float; sinhf: c_float; coshf: c_float; tanhf: c_float; asinhf: c_float;
    acoshf: c_float; atanhf: c_float; expf: c_float; exp2f: c_float; exp10f: c_float;
    expm1f: c_float; logf: c_float; log2f: c_float; log10f: c_float; log1pf: c_float;
    cbrtf: c_float; erff: c_float; erfcf: c_float; tgammaf: c_float; lgammaf: c_float;
    sin: c_double; cos: c_double; tan: c_double; asin: c_double; acos: c_double;
    atan: c_double; sinh: c_double; cosh: c_double; tanh: c_double; asinh: c_double;
    acosh: c_double; atanh: c_double; exp: c_double; exp2: c_double; exp10: c_double;
    expm1: c_double; log: c_double; log2: c_double; log10: c_double; log1p: c_double;
    cbrt: c_double; erf: c_double; erfc: c_double; tgamma: c_double; lgamma: c_double;
}

binary! {
    atan2f: c_float; powf: c_float; hypotf: c_float;
    atan2: c_double; pow: c_double; hypot: c_double;
}

/// `sincosf`: LLVM merges a `sin` and a `cos` of one argument into this call.
///
/// # Safety
/// `s` and `c` must be valid for writes (the C contract).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sincosf(x: c_float, s: *mut c_float, c: *mut c_float) {
    let (sin, cos) = libm::sincosf(x);
    // SAFETY: the caller passes two writable floats, as C's sincosf requires.
    unsafe {
        *s = sin;
        *c = cos;
    }
}

/// `sincos`, the `f64` twin of [`sincosf`].
///
/// # Safety
/// `s` and `c` must be valid for writes (the C contract).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn sincos(x: c_double, s: *mut c_double, c: *mut c_double) {
    let (sin, cos) = libm::sincos(x);
    // SAFETY: the caller passes two writable doubles, as C's sincos requires.
    unsafe {
        *s = sin;
        *c = cos;
    }
}

/// `lgamma_r`, reentrant `lgamma` with the sign out.
///
/// # Safety
/// `sign` must be valid for writes (the C contract).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lgamma_r(x: c_double, sign: *mut c_int) -> c_double {
    let (v, s) = libm::lgamma_r(x);
    // SAFETY: the caller passes a writable int, as C's lgamma_r requires.
    unsafe { *sign = s };
    v
}

/// `lgammaf_r`, the `f32` twin of [`lgamma_r`].
///
/// # Safety
/// `sign` must be valid for writes (the C contract).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lgammaf_r(x: c_float, sign: *mut c_int) -> c_float {
    let (v, s) = libm::lgammaf_r(x);
    // SAFETY: the caller passes a writable int, as C's lgammaf_r requires.
    unsafe { *sign = s };
    v
}
