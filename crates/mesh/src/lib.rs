//! # fdem-mesh: meshes and deformable constant-strain triangles at finite strain
//!
//! Reading ([`read_mesh`]: Gmsh 4.1 ASCII/binary, Gmsh 2.2 ASCII, JSON), validating and
//! holding a triangle mesh ([`Mesh`]: nodes, CCW triangles, named physical groups, material
//! regions, edges, adjacency, boundary), materials ([`Material`]), the per-triangle
//! precomputation ([`Elements`]), the internal-force kernel ([`Elements::internal_forces`]) and
//! its exact directional derivative ([`Elements::force_derivative`]), stresses, energies,
//! frequency bounds, the explode operation ([`explode()`]) and the small-strain sparse stiffness
//! ([`Elements::stiffness`]).
//!
//! ## Equations (Munjiza 2004, sec. 4.7; see docs/mesh.md)
//!
//! ```text
//! G0 = [X1-X0 | X2-X0]   G = [x1-x0 | x2-x0]   F = G G0^-1   J = det F   B = F F^T
//! Munjiza:      sigma = 2 mu e + lam* tr(e) I,         e = (B - I)/2
//! neo-Hookean:  sigma = (mu (B - I) + lam* ln J I)/J,  W = mu/2 (tr B - 2 - 2 ln J) + lam*/2 (ln J)^2
//! viscous:      sigma_v = eta d,  d = sym(Gv G^-1),    eta = 2 xi h sqrt(E rho)
//! forces:       f_a = -A t sigma grad N_a = -(t/2) sigma rot(x_c - x_b)
//! lumped mass:  m_a = rho A0 t / 3
//! frequency:    omega_e^2 <= 3 c_p^2 sum_a |grad N_a|^2,  c_p^2 = (lam* + 2 mu)/rho
//! ```
//! `mu = E/(2(1+nu))`; `lam* = E nu/((1+nu)(1-2nu))` in plane strain, `E nu/(1-nu^2)` in plane
//! stress. A rigid rotation gives `B = I` and no stress; `F -> QF` gives `sigma -> Q sigma Q^T`.

pub mod elements;
pub mod error;
pub mod excerpt;
pub mod explode;
pub mod forces;
pub mod ids;
pub mod io;
pub mod material;
pub mod mesh;
pub mod nodes;
pub mod stiffness;
pub mod stress;
pub mod triangle;

pub use elements::{Elements, MaterialConsts, TriData};
pub use error::MeshError;
pub use excerpt::{excerpt, shorten, shorten_to};
pub use explode::{Exploded, InternalEdge, explode};
pub use forces::ForceScratch;
pub use ids::{EdgeId, NodeId, RegionId, TriId};
pub use io::{JsonGroup, JsonMesh, read_mesh, read_mesh_bytes, write_json};
pub use material::{ElasticLaw, Material, PlaneKind};
pub use mesh::{Mesh, MeshEdge, PhysicalGroup, RawMesh, tri_area};
pub use nodes::NodeArrays;
pub use stiffness::{reference_gradients, solve_static};
pub use stress::Stress;
