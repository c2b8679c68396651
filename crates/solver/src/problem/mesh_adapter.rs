//! The adapter to the mesh crate: reads a mesh file into the solver's [`MeshInput`], converts
//! scene materials into the mesh crate's, and describes a mesh for `fdem info`.

use std::fmt::Write as _;
use std::path::Path;

use fdem_mesh::{ElasticLaw, Elements, Material, Mesh, PlaneKind};

use crate::input::mesh_input::MeshInput;
use crate::input::scene::{Law, MaterialSpec, Plane};
use crate::problem::model::Model;

/// Reads a mesh file (Gmsh `.msh` or JSON) with the mesh crate.
pub fn read(path: &Path) -> Result<Mesh, String> {
    fdem_mesh::read_mesh(path).map_err(|e| e.to_string())
}

/// The solver's view of a mesh: nodes, triangles with their surface group, node and edge groups.
pub fn to_input(mesh: &Mesh) -> MeshInput {
    let mut input = MeshInput {
        nodes: mesh.nodes.clone(),
        triangles: mesh.triangles.clone(),
        triangle_group: mesh
            .tri_region
            .iter()
            .map(|r| mesh.regions[r.0 as usize].clone())
            .collect(),
        ..Default::default()
    };
    for g in &mesh.groups {
        input
            .node_groups
            .insert(g.name.clone(), g.nodes.iter().map(|n| n.0).collect());
        if g.dim == 1 {
            input.edge_groups.insert(
                g.name.clone(),
                g.edges.iter().map(|e| [e[0].0, e[1].0]).collect(),
            );
        }
    }
    input
}

/// The mesh crate's material for a scene material of thickness `thickness` and element
/// viscosity ratio `xi`.
pub fn material(spec: &MaterialSpec, thickness: f64, xi: f64) -> Material {
    Material {
        law: match spec.law {
            Law::LinearElastic => ElasticLaw::Munjiza,
            Law::NeoHookean => ElasticLaw::NeoHookean,
        },
        plane: match spec.plane {
            Plane::Stress => PlaneKind::Stress,
            Plane::Strain => PlaneKind::Strain,
        },
        youngs_modulus: spec.young,
        poisson_ratio: spec.poisson,
        density: spec.density,
        thickness,
        damping_ratio: xi,
    }
}

/// The model's triangles prepared for the force kernels, with viscosity ratio `xi`.
pub fn elements(model: &Model, xi: f64) -> Result<Elements, String> {
    let mats: Vec<Material> = model
        .materials
        .iter()
        .map(|(s, t)| {
            let mut m = material(s, *t, xi);
            // mass scaling: the density of the frequency bounds is the scaled one
            if let Some((f, _)) = &model.mass_scaling {
                m.density *= f;
            }
            m
        })
        .collect();
    if let Some(r) = &model.relaxation_masses {
        // equal-step masses: each triangle its own row, with the density of its mass
        let rows: Vec<Material> = (model.tri_material.iter().zip(&r.density_factor))
            .map(|(&mi, f)| {
                let mut m = mats[mi as usize];
                m.density *= f;
                m
            })
            .collect();
        let ids: Vec<u32> = (0..rows.len() as u32).collect();
        return Elements::from_arrays(&model.x0, &model.triangles, &ids, &rows)
            .map_err(|e| e.to_string());
    }
    Elements::from_arrays(&model.x0, &model.triangles, &model.tri_material, &mats)
        .map_err(|e| e.to_string())
}

/// Counts, groups, bounding box and element sizes of a mesh file, as text.
pub fn describe_file(path: &Path) -> Result<String, String> {
    let mesh = read(path)?;
    Ok(describe(&mesh, &path.display().to_string()))
}

/// Counts, groups, bounding box and element sizes of a mesh, as text.
pub fn describe(mesh: &Mesh, name: &str) -> String {
    let mut s = String::new();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &mesh.nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let (mut hmin, mut hmax, mut area) = (f64::INFINITY, 0.0f64, 0.0);
    for t in &mesh.triangles {
        let p = t.map(|i| mesh.nodes[i as usize]);
        let a = fdem_mesh::tri_area(&mesh.nodes, *t);
        let longest = (0..3)
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % 3]);
                ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt()
            })
            .fold(0.0, f64::max);
        let h = 2.0 * a / longest;
        hmin = hmin.min(h);
        hmax = hmax.max(h);
        area += a;
    }
    let _ = writeln!(s, "mesh {name}");
    let _ = writeln!(
        s,
        "  {} nodes, {} triangles, {} boundary edges, area {:.6e} m^2",
        mesh.nodes.len(),
        mesh.triangles.len(),
        mesh.boundary_edges.len(),
        area
    );
    let _ = writeln!(
        s,
        "  bounding box [{:.6e}, {:.6e}] x [{:.6e}, {:.6e}] m",
        lo[0], hi[0], lo[1], hi[1]
    );
    let _ = writeln!(
        s,
        "  element size h = 2A/longest edge: {hmin:.4e} to {hmax:.4e} m"
    );
    let _ = writeln!(s, "  physical groups:");
    for g in &mesh.groups {
        let what = match g.dim {
            0 => format!("{} nodes", g.nodes.len()),
            1 => format!("{} edges, {} nodes", g.edges.len(), g.nodes.len()),
            _ => format!("{} triangles, {} nodes", g.triangles.len(), g.nodes.len()),
        };
        let _ = writeln!(
            s,
            "    {:<24} dim {} tag {:<4} {what}",
            g.name, g.dim, g.tag
        );
    }
    s
}
