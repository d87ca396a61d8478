//! [`SceneError`]: what is wrong with a scene, from reading to building.

/// What is wrong with a scene.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The RON text could not be read (the message has line:column).
    #[error("scene file: {0}")]
    Parse(String),
    /// A value is out of its allowed range.
    #[error("scene field `{field}`: {message}")]
    Field {
        /// The field's path, e.g. `fluid.blocks[0].max`.
        field: String,
        /// What is allowed and what was given.
        message: String,
    },
}
