//! A scanned mesh for the effects: the Stanford bunny the repository keeps
//! (`spvg-report/assets/bunny.obj`, loaded with `tobj`), on a ground plane, under a
//! perspective camera that orbits it with sub-pixel Halton jitter ([`scene`]); its
//! G-buffer (depth, reprojected depth, motion vectors, position, normal) ray cast through
//! a bounding volume hierarchy ([`bvh`]); and ambient occlusion on it, traced on the CPU,
//! with a converged reference per frame ([`ao`]). Content nobody here modelled: the
//! motion section runs it beside its procedural scenes (`crate::motion::mesh`).
//!
//! One concept per module, each importing only those listed before it: [`bvh`],
//! [`scene`], [`ao`], [`sss`] (the subsurface section's inputs).

pub mod ao;
pub mod bvh;
pub mod scene;
pub mod sss;
