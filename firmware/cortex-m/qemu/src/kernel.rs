//! f32 against f64 on the Cortex-M4F: one attitude-filter step written once
//! for both types (a macro), so the instruction counts compare the same
//! arithmetic. The Cortex-M4F's FPU does single precision only: f32 add, mul
//! and div are one instruction each, f64 ones are calls into the compiler's
//! software floating point (`__aeabi_dadd`, `__aeabi_dmul`, …).
//!
//! The step is the core of a Mahony-type update — what every filter of
//! clino-core does per sample: the gravity direction predicted by the
//! attitude v = R(q)ᵀ e_z, the error e = â × v against the normalised
//! accelerometer â, the corrected rate ω + k e, first-order quaternion
//! integration q ← q + ½ q ⊗ (0, ω) dt, and renormalisation (two square
//! roots, two divisions, ~70 multiplications and additions).

macro_rules! kernel {
    ($name:ident, $f:ty, $sqrt:path) => {
        /// One filter step (module docs) in this float type.
        #[inline(never)]
        pub fn $name(q: [$f; 4], w: [$f; 3], a: [$f; 3], k: $f, dt: $f) -> [$f; 4] {
            let [q0, q1, q2, q3] = q;
            // v = R(q)ᵀ e_z: the third row of R(q) (Hamilton, body → nav)
            let vx = 2.0 * (q1 * q3 - q0 * q2);
            let vy = 2.0 * (q0 * q1 + q2 * q3);
            let vz = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3;
            let na = $sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            let (ax, ay, az) = (a[0] / na, a[1] / na, a[2] / na);
            // e = â × v
            let ex = ay * vz - az * vy;
            let ey = az * vx - ax * vz;
            let ez = ax * vy - ay * vx;
            let (gx, gy, gz) = (w[0] + k * ex, w[1] + k * ey, w[2] + k * ez);
            // q̇ = ½ q ⊗ (0, ω)
            let h = 0.5 * dt;
            let p0 = q0 + h * (-q1 * gx - q2 * gy - q3 * gz);
            let p1 = q1 + h * (q0 * gx + q2 * gz - q3 * gy);
            let p2 = q2 + h * (q0 * gy - q1 * gz + q3 * gx);
            let p3 = q3 + h * (q0 * gz + q1 * gy - q2 * gx);
            let n = $sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3);
            [p0 / n, p1 / n, p2 / n, p3 / n]
        }
    };
}

/// Square root by the FPU's `vsqrt.f32` (14 cycles on a Cortex-M4F): what an
/// f32 build would use (`libm::sqrtf` is a bit-by-bit software routine).
/// Rust 1.88 has no stable f32 `sqrt` in `core` and refuses FPU register
/// operands for this target in `asm!`, so s0 is saved and the value moved
/// through it: five instructions where a compiler intrinsic would need one.
#[inline(always)]
pub fn vsqrt(x: f32) -> f32 {
    let r: u32;
    // SAFETY: FPU instructions on s0, which is saved and restored on the stack
    // (the FPU is enabled by cortex-m-rt's reset handler on an `eabihf` target).
    unsafe {
        core::arch::asm!(
            "vpush {{s0}}",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {r}, s0",
            "vpop {{s0}}",
            x = in(reg) x.to_bits(),
            r = out(reg) r,
        );
    }
    f32::from_bits(r)
}

kernel!(step_f64, f64, libm::sqrt);
kernel!(step_f32_libm, f32, libm::sqrtf);
kernel!(step_f32_fpu, f32, vsqrt);
