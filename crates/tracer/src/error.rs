//! What can be wrong with a scene, and the answer of a cancelled render.

/// A scene the renderer refuses, found by [`crate::Renderer::new`] before
/// anything is built. Each message names the item (object, material or
/// light index, as in [`crate::Scene`]) and says what to fix.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// Width or height is 0.
    #[error("the image is {width}×{height} pixels; set both width and height to at least 1")]
    EmptyImage {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
    },
    /// More pixels than [`crate::MAX_PIXELS`] (the framebuffer would not fit
    /// in memory, or the resolution is a typo).
    #[error("the image is {width}×{height} pixels, more than the {max} the renderer accepts; lower the resolution")]
    ImageTooLarge {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
        /// The limit.
        max: u64,
    },
    /// `spp` is 0.
    #[error("samples per pixel is 0; set spp to at least 1")]
    ZeroSamples,
    /// The scene asks for path tracing, but nothing in it emits light.
    #[error("the scene asks for path tracing (integrator: Path), but nothing emits light: give a material Emissive(...) to some object, add a light, or set a non-black background")]
    NothingEmits,
    /// The reconstruction filter's parameters are out of range.
    #[error("settings: the filter {filter} is unusable: its radius must be in (0, 16] pixels and its sigma > 0")]
    BadFilter {
        /// The filter, described.
        filter: String,
    },
    /// A number in the settings is NaN or infinite.
    #[error("settings: the {what} is not finite; give finite numbers")]
    SettingNotFinite {
        /// Which setting.
        what: &'static str,
    },
    /// A camera position or vector is NaN or infinite.
    #[error("camera: the {what} is not finite; give finite coordinates")]
    CameraNotFinite {
        /// `eye`, `look_at`, `up` or a projection parameter.
        what: &'static str,
    },
    /// `eye == look_at`: no view direction.
    #[error(
        "camera: eye and look_at are the same point; move look_at to where the camera should look"
    )]
    CameraEyeAtLookAt,
    /// `up` is zero or parallel to the view direction.
    #[error("camera: the up vector is zero or parallel to the view direction; pick an up vector across it (e.g. +y)")]
    CameraUpParallel,
    /// A projection parameter is out of range.
    #[error("camera: {what} is {value}, but must be {range}")]
    CameraProjection {
        /// The parameter.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The accepted range, in words.
        range: &'static str,
    },
    /// An object refers to a material that does not exist.
    #[error("object {object}: material index {material} is out of range (the scene has {count} materials)")]
    MaterialOutOfRange {
        /// Object index.
        object: usize,
        /// The index it gave.
        material: u32,
        /// How many materials there are.
        count: usize,
    },
    /// A sphere with radius ≤ 0 or not finite.
    #[error("object {object}: sphere radius is {radius}; it must be a finite number > 0")]
    BadRadius {
        /// Object index.
        object: usize,
        /// The radius.
        radius: f64,
    },
    /// A coordinate of an object is NaN or infinite.
    #[error("object {object}: the {what} is not finite; give finite coordinates")]
    NotFinite {
        /// Object index.
        object: usize,
        /// Which field.
        what: &'static str,
    },
    /// A plane's normal is zero.
    #[error("object {object}: the plane's normal is zero; give a non-zero normal")]
    ZeroNormal {
        /// Object index.
        object: usize,
    },
    /// A box with `min > max` on some axis.
    #[error("object {object}: the box has min > max on some axis; swap the corners")]
    InvertedCuboid {
        /// Object index.
        object: usize,
    },
    /// A mesh triangle refers to a vertex that does not exist.
    #[error("object {object} (mesh {mesh:?}): triangle {triangle} uses vertex {index}, but the mesh has {vertices} vertices")]
    MeshIndexOutOfRange {
        /// Object index.
        object: usize,
        /// Mesh name.
        mesh: String,
        /// Triangle index in the mesh.
        triangle: usize,
        /// The bad vertex index.
        index: u32,
        /// How many positions the mesh has.
        vertices: usize,
    },
    /// A mesh has normals or uvs, but not one per position.
    #[error("object {object} (mesh {mesh:?}): {count} {attribute} for {vertices} positions; give none or one per position")]
    MeshAttributeCount {
        /// Object index.
        object: usize,
        /// Mesh name.
        mesh: String,
        /// `normals` or `uvs`.
        attribute: &'static str,
        /// How many there are.
        count: usize,
        /// How many positions there are.
        vertices: usize,
    },
    /// A mesh vertex position or normal is NaN or infinite.
    #[error("object {object} (mesh {mesh:?}): {attribute} {vertex} is not finite")]
    MeshNotFinite {
        /// Object index.
        object: usize,
        /// Mesh name.
        mesh: String,
        /// `position` or `normal`.
        attribute: &'static str,
        /// Vertex index.
        vertex: usize,
    },
    /// A material parameter is out of range.
    #[error("material {material}: {reason}")]
    BadMaterial {
        /// Material index.
        material: usize,
        /// What is wrong and what to do.
        reason: &'static str,
    },
    /// An instance's transform cannot be used.
    #[error("object {object}: {reason}")]
    BadTransform {
        /// Object index.
        object: usize,
        /// What is wrong and what to do.
        reason: &'static str,
    },
    /// A light parameter is out of range.
    #[error("light {light}: {reason}")]
    BadLight {
        /// Light index.
        light: usize,
        /// What is wrong and what to do.
        reason: &'static str,
    },
    /// A texture or a material's texture maps are invalid (a reference to
    /// a texture that does not exist, a factor out of range, a procedural
    /// parameter out of range). The reason names the material or texture.
    #[error("textures: {reason}")]
    BadTextures {
        /// What is wrong, naming the material or texture.
        reason: String,
    },
    /// A sphere set has colours, but not one per sphere.
    #[error("object {object}: the sphere set has {colors} colours for {spheres} spheres; give none or one per sphere")]
    SphereSetColors {
        /// Object index.
        object: usize,
        /// How many colours.
        colors: usize,
        /// How many spheres.
        spheres: usize,
    },
    /// A sphere of a sphere set is unusable.
    #[error("object {object}: sphere {sphere} of the set: {reason}")]
    BadSetSphere {
        /// Object index.
        object: usize,
        /// The sphere's index in the set.
        sphere: usize,
        /// What is wrong and what to do.
        reason: &'static str,
    },
    /// More primitives than a `u32` index can name.
    #[error(
        "the scene has {count} primitives (triangles count one each), more than 2^32 − 1; split it"
    )]
    TooManyPrimitives {
        /// How many.
        count: usize,
    },
}

/// The answer of a render stopped through its cancel flag.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, thiserror::Error)]
#[error("the render was cancelled")]
pub struct Cancelled;
