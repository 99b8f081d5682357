//! `articulated`: rigid-body dynamics generated at compile time from a chain description.
//!
//! This crate is what users depend on. It re-exports the macros, the chain [`model`], the
//! [`Scalar`] trait and the [`reference`] dynamics.
//!
//! # Conventions
//! SI units. Spatial vectors are **angular first** (Featherstone): a motion is `[ω; v]`, a force
//! `[n; f]`. Pinocchio orders them linear first; convert when comparing.
#![cfg_attr(not(feature = "std"), no_std)]

pub use articulated_dynamics::scalar::{self, Scalar};
#[cfg(feature = "alloc")]
pub use articulated_dynamics::{model, reference};
