//! The shader modules the plugin registers for WESL shaders to import: the `spvg-shaders`
//! WGSL library, and the bindings of an adaptive effect.

use bevy::app::App;
use bevy::asset::{Assets, Handle, uuid_handle};
use bevy::shader::Shader;

/// The handle the library is stored under in `Assets<Shader>`.
pub const SHADER_LIBRARY_HANDLE: Handle<Shader> =
    uuid_handle!("6f1e2f0a-5b7d-4c3e-9a61-2d8c0f4b7e15");

/// The module path a Bevy WESL shader imports the library from:
/// `import spvg_bevy::spvg::{spvg_Params, spvg_pcg3d16};`. Every public name of the library
/// starts with `spvg_` (see `spvg-shaders`).
pub const SHADER_IMPORT_PATH: &str = "spvg_bevy::spvg";

/// The handle the adaptive effect's bindings module is stored under in `Assets<Shader>`.
pub const EFFECT_SHADER_HANDLE: Handle<Shader> =
    uuid_handle!("2b8c5e71-0d4f-4a9b-8e36-91c7f04a5d23");

/// The module path of an adaptive effect's bindings and helpers (see
/// [`AdaptiveEffect`](crate::AdaptiveEffect)):
/// `import spvg_bevy::effect::{EffectOutput, sample_count};`.
pub const EFFECT_IMPORT_PATH: &str = "spvg_bevy::effect";

/// The asset paths the modules are registered under; Bevy derives the import paths
/// [`SHADER_IMPORT_PATH`] and [`EFFECT_IMPORT_PATH`] from them (an `embedded://` path's
/// crate and file stem).
const PATH: &str = "embedded://spvg_bevy/spvg.wesl";
const EFFECT_PATH: &str = "embedded://spvg_bevy/effect.wesl";

/// Stores both modules (plain WGSL is WESL) in `Assets<Shader>`, where Bevy's shader cache
/// registers their import paths. Without Bevy's shader assets (no render plugins) it does
/// nothing.
pub(crate) fn register(app: &mut App) {
    if let Some(mut shaders) = app.world_mut().get_resource_mut::<Assets<Shader>>() {
        // A UUID id never fails (`Assets::insert`).
        let _ = shaders.insert(
            SHADER_LIBRARY_HANDLE.id(),
            Shader::from_wesl(spvg_shaders::WGSL, PATH),
        );
        let _ = shaders.insert(
            EFFECT_SHADER_HANDLE.id(),
            Shader::from_wesl(include_str!("effect.wesl"), EFFECT_PATH),
        );
    }
}
