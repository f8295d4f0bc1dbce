//! The `spvg-shaders` WGSL library as a Bevy shader module that WESL shaders import.

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

/// The asset path the module is registered under; Bevy derives the import path
/// [`SHADER_IMPORT_PATH`] from it (an `embedded://` path's crate and file stem).
const PATH: &str = "embedded://spvg_bevy/spvg.wesl";

/// Stores the library (plain WGSL is WESL) in `Assets<Shader>`, where Bevy's shader cache
/// registers its import path. Without Bevy's shader assets (no render plugins) it does
/// nothing.
pub(crate) fn register(app: &mut App) {
    if let Some(mut shaders) = app.world_mut().get_resource_mut::<Assets<Shader>>() {
        // A UUID id never fails (`Assets::insert`).
        let _ = shaders.insert(
            SHADER_LIBRARY_HANDLE.id(),
            Shader::from_wesl(spvg_shaders::WGSL, PATH),
        );
    }
}
