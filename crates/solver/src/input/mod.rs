//! What a scene is given as: the JSON scene format ([`scene`], `docs/scene-format.md`), one
//! body's mesh as the solver needs it ([`mesh_input`]), the schemes a scene may name
//! ([`schemes`]), and every name the scene refers to resolved once against the bodies'
//! meshes ([`resolve`]). Nothing here depends on the prepared problem or the stages.

pub mod arrays;
pub mod mesh_input;
pub mod resolve;
pub mod scene;
pub mod schemes;
