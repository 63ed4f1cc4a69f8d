//! Scalar maths for `no_std`: the platform's libm through `std` when the
//! `std` feature is on (faster on desktop), the pure-Rust `libm` otherwise.
#![allow(dead_code)]

#[cfg(feature = "std")]
mod imp {
    #[inline(always)]
    pub fn sqrt(x: f64) -> f64 {
        x.sqrt()
    }
    #[inline(always)]
    pub fn sin(x: f64) -> f64 {
        x.sin()
    }
    #[inline(always)]
    pub fn cos(x: f64) -> f64 {
        x.cos()
    }
    #[inline(always)]
    pub fn atan2(y: f64, x: f64) -> f64 {
        y.atan2(x)
    }
    #[inline(always)]
    pub fn asin(x: f64) -> f64 {
        x.asin()
    }
    #[inline(always)]
    pub fn acos(x: f64) -> f64 {
        x.acos()
    }
    #[inline(always)]
    pub fn exp(x: f64) -> f64 {
        x.exp()
    }
    #[inline(always)]
    pub fn ln(x: f64) -> f64 {
        x.ln()
    }
    #[inline(always)]
    pub fn tan(x: f64) -> f64 {
        x.tan()
    }
}

#[cfg(not(feature = "std"))]
mod imp {
    #[inline(always)]
    pub fn sqrt(x: f64) -> f64 {
        libm::sqrt(x)
    }
    #[inline(always)]
    pub fn sin(x: f64) -> f64 {
        libm::sin(x)
    }
    #[inline(always)]
    pub fn cos(x: f64) -> f64 {
        libm::cos(x)
    }
    #[inline(always)]
    pub fn atan2(y: f64, x: f64) -> f64 {
        libm::atan2(y, x)
    }
    #[inline(always)]
    pub fn asin(x: f64) -> f64 {
        libm::asin(x)
    }
    #[inline(always)]
    pub fn acos(x: f64) -> f64 {
        libm::acos(x)
    }
    #[inline(always)]
    pub fn exp(x: f64) -> f64 {
        libm::exp(x)
    }
    #[inline(always)]
    pub fn ln(x: f64) -> f64 {
        libm::log(x)
    }
    #[inline(always)]
    pub fn tan(x: f64) -> f64 {
        libm::tan(x)
    }
}

pub use imp::*;

/// `x` clamped to [-1, 1] (for asin/acos of rounded cosines).
#[inline(always)]
pub fn clamp1(x: f64) -> f64 {
    x.clamp(-1.0, 1.0)
}
