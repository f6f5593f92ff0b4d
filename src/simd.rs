//! Run-time choice of SIMD kernels. Release builds target baseline x86-64 (farm hosts must
//! produce identical bits, so no `target-cpu=native`); hot kernels are compiled twice, SSE2 and
//! AVX2, with the same float operations in the same order (never fused multiply-adds), and the
//! AVX2 copy runs where the CPU has it.

/// Whether the AVX2 kernels run on this CPU. `ENVSHADOW_NO_AVX2` (any value) forces the SSE2
/// kernels, so one host can check that both write the same bits (tests/it/simd.rs).
#[cfg(target_arch = "x86_64")]
pub fn has_avx2() -> bool {
    use std::sync::OnceLock;
    static AVX2: OnceLock<bool> = OnceLock::new();
    *AVX2.get_or_init(|| {
        std::env::var_os("ENVSHADOW_NO_AVX2").is_none() && is_x86_feature_detected!("avx2")
    })
}

#[cfg(not(target_arch = "x86_64"))]
pub fn has_avx2() -> bool {
    false
}

/// Which copy of the hot kernels (shading, BVH nodes and leaves) this process runs: "avx2",
/// "sse2", or "scalar" off x86-64. For `envshadow version --kernels`, so a test can see that
/// `ENVSHADOW_NO_AVX2` switched the kernels instead of assuming it.
pub fn kernels() -> &'static str {
    if cfg!(not(target_arch = "x86_64")) {
        "scalar"
    } else if has_avx2() {
        "avx2"
    } else {
        "sse2"
    }
}
