//! Geometry read from files: meshes (STL, OBJ, MuJoCo's `.msh`), their mass properties as
//! MuJoCo computes them and their convex hulls, which collision uses; height fields (PNG, MuJoCo's
//! binary grid, inline or zeros) and a ray's walk over a height field's grid.

pub(crate) mod grid_walk;
pub mod hfield;
pub mod hull;
pub mod mass;
pub mod mesh;
pub mod read;

pub use hfield::HField;
pub use hull::Hull;
pub use mass::{MeshFrame, MeshInertia};
pub use mesh::{Mesh, MeshPlacement};
pub use read::{read_mesh, RawMesh};
