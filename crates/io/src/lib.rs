//! Everything that touches the outside world: RON scenes, OBJ and glTF meshes,
//! PNG and EXR images. **The only crate that reads or writes files.**
#![warn(missing_docs)]
