//! Gmsh `.msh` readers: format 4.1 (ASCII and binary) and 2.2 (ASCII), with `$PhysicalNames`.
//!
//! Points (type 15), 2-node lines (type 1) and 3-node triangles (type 2) are read; any other
//! element type is an error. The z coordinate must be the same for all nodes and is dropped.

use super::cursor::Cursor;
use crate::error::MeshError;
use crate::excerpt::excerpt;
use crate::ids::{NodeId, TriId};
use crate::mesh::{PhysicalGroup, RawMesh};
use std::collections::{BTreeMap, HashMap};

/// Gmsh element type names, for messages.
fn type_name(t: i64) -> &'static str {
    match t {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "3-node line",
        9 => "6-node triangle",
        10 => "9-node quadrangle",
        11 => "10-node tetrahedron",
        15 => "point",
        16 => "8-node quadrangle",
        _ => "unknown type",
    }
}

/// Groups being collected, keyed by (dim, physical tag).
#[derive(Default)]
struct Groups {
    names: HashMap<(u8, i64), String>,
    map: BTreeMap<(u8, i64), PhysicalGroup>,
}

impl Groups {
    fn get(&mut self, dim: u8, tag: i64) -> &mut PhysicalGroup {
        let name = self
            .names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("{dim}:{tag}"));
        self.map.entry((dim, tag)).or_insert_with(|| PhysicalGroup {
            name,
            dim,
            tag,
            nodes: Vec::new(),
            edges: Vec::new(),
            triangles: Vec::new(),
        })
    }
}

/// Collects nodes and elements with their tags, then builds the [`RawMesh`].
#[derive(Default)]
struct Builder {
    node_index: HashMap<u64, u32>,
    node_tags: Vec<u64>,
    nodes: Vec<[f64; 2]>,
    z0: Option<f64>,
    triangles: Vec<[u32; 3]>,
    tri_tags: Vec<u64>,
    groups: Groups,
}

impl Builder {
    fn add_node(&mut self, c: &Cursor, tag: u64, x: f64, y: f64, z: f64) -> Result<(), MeshError> {
        if !(x.is_finite() && y.is_finite() && z.is_finite()) {
            return Err(MeshError::NonFinite {
                path: c.path.to_string(),
                tag,
            });
        }
        match self.z0 {
            None => self.z0 = Some(z),
            Some(z0) => {
                if (z - z0).abs() > 1e-9 * (1.0 + z0.abs() + x.abs() + y.abs()) {
                    return Err(c.err(format!(
                        "node {tag} has z = {z}, others z = {z0}: fdem reads plane meshes in the x-y plane"
                    )));
                }
            }
        }
        let i = self.nodes.len() as u32;
        if self.node_index.insert(tag, i).is_some() {
            return Err(MeshError::DuplicateNodeTag {
                path: c.path.to_string(),
                node: tag,
            });
        }
        self.node_tags.push(tag);
        self.nodes.push([x, y]);
        Ok(())
    }

    fn node(&self, c: &Cursor, element: u64, tag: u64) -> Result<u32, MeshError> {
        self.node_index
            .get(&tag)
            .copied()
            .ok_or_else(|| MeshError::UnknownNode {
                path: c.path.to_string(),
                element,
                node: tag,
            })
    }

    /// Adds one element of Gmsh type `ty` with node tags `nt`, in the physical groups `phys`.
    fn add_element(
        &mut self,
        c: &Cursor,
        tag: u64,
        ty: i64,
        nt: &[u64],
        phys: &[i64],
    ) -> Result<(), MeshError> {
        match ty {
            15 => {
                let n = NodeId(self.node(c, tag, nt[0])?);
                for &p in phys {
                    self.groups.get(0, p).nodes.push(n);
                }
            }
            1 => {
                let e = [
                    NodeId(self.node(c, tag, nt[0])?),
                    NodeId(self.node(c, tag, nt[1])?),
                ];
                for &p in phys {
                    self.groups.get(1, p).edges.push(e);
                }
            }
            2 => {
                let t = [
                    self.node(c, tag, nt[0])?,
                    self.node(c, tag, nt[1])?,
                    self.node(c, tag, nt[2])?,
                ];
                let id = TriId(self.triangles.len() as u32);
                self.triangles.push(t);
                self.tri_tags.push(tag);
                for &p in phys {
                    self.groups.get(2, p).triangles.push(id);
                }
            }
            _ => unreachable!("checked by nodes_per_type"),
        }
        Ok(())
    }

    fn finish(self, path: &str) -> RawMesh {
        let mut groups = self.groups;
        // Named groups with no elements still exist (they give an empty set, not an error).
        let keys: Vec<_> = groups.names.keys().copied().collect();
        for (d, t) in keys {
            groups.get(d, t);
        }
        RawMesh {
            path: path.to_string(),
            node_tags: self.node_tags,
            nodes: self.nodes,
            triangles: self.triangles,
            tri_tags: self.tri_tags,
            groups: groups.map.into_values().collect(),
        }
    }
}

fn nodes_per_type(c: &Cursor, element: u64, ty: i64) -> Result<usize, MeshError> {
    match ty {
        15 => Ok(1),
        1 => Ok(2),
        2 => Ok(3),
        _ => Err(MeshError::UnsupportedElement {
            path: c.path.to_string(),
            element,
            gmsh_type: ty,
            name: type_name(ty),
        }),
    }
}

fn physical_names(c: &mut Cursor, g: &mut Groups) -> Result<(), MeshError> {
    let n = c.parse_count_ascii()?;
    for _ in 0..n {
        let line = c.line_text()?;
        let mut it = line.splitn(3, char::is_whitespace);
        let dim: u8 = it
            .next()
            .and_then(|s| s.parse().ok())
            .filter(|d| *d <= 3)
            .ok_or_else(|| c.err(format!("bad physical name line \"{}\"", excerpt(line))))?;
        let tag: i64 = it
            .next()
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| c.err(format!("bad physical name line \"{}\"", excerpt(line))))?;
        let name = it.next().unwrap_or("").trim().trim_matches('"').to_string();
        g.names.insert((dim, tag), name);
    }
    c.expect("$EndPhysicalNames")
}

impl Cursor<'_> {
    fn parse_count_ascii(&mut self) -> Result<usize, MeshError> {
        let bin = self.binary;
        self.binary = false;
        let r = self.count(2, "physical name");
        self.binary = bin;
        r
    }
}

/// Reads a Gmsh file (4.1 ASCII/binary or 2.2 ASCII) from bytes.
pub(crate) fn read_gmsh(bytes: &[u8], path: &str) -> Result<RawMesh, MeshError> {
    let mut c = Cursor::new(bytes, path);
    let h = c.line_text()?;
    if h.trim() != "$MeshFormat" {
        return Err(c.err("not a Gmsh mesh: the file does not start with $MeshFormat"));
    }
    let version = c.token()?.to_string();
    let file_type = c.token()?;
    let data_size: usize = c
        .token()?
        .parse()
        .map_err(|_| c.err("bad data size in $MeshFormat"))?;
    let binary = match file_type {
        "0" => false,
        "1" => true,
        t => {
            return Err(c.err(format!("bad file type \"{}\" in $MeshFormat", excerpt(t))));
        }
    };
    if binary {
        // One '\n', then the int 1 written in the writer's byte order.
        c.pos += 1;
        c.binary = true;
        let one = c.int()?;
        c.binary = false;
        if one != 1 {
            if one == 1 << 24 {
                return Err(MeshError::WrongEndianness {
                    path: path.to_string(),
                });
            }
            return Err(c.err("corrupt binary header: the endianness marker is not 1"));
        }
    }
    c.expect("$EndMeshFormat")?;
    match (version.as_str(), binary) {
        ("4.1", _) => {
            if data_size != 8 && data_size != 4 {
                return Err(c.err(format!("unsupported size_t of {data_size} bytes")));
            }
            c.size_t = data_size;
            read41(c, binary)
        }
        ("2.2", false) => read22(c),
        _ => Err(MeshError::UnsupportedVersion {
            path: path.to_string(),
            version: if binary {
                format!("{version} binary")
            } else {
                version
            },
        }),
    }
}

/// A line where a section should start that neither reader knows: a section of its own
/// (`$Comments`, `$Periodic`, ...) is skipped whole; anything else is an error that shows it.
fn other_section(c: &mut Cursor, s: &str) -> Result<(), MeshError> {
    if s.starts_with('$') && !s.starts_with("$End") && s.len() > 1 {
        c.skip_section(s)
    } else {
        Err(c.err(format!(
            "expected a section such as $Nodes, found \"{}\"",
            excerpt(s)
        )))
    }
}

/// The end of a file: the mesh, once both `$Nodes` and `$Elements` were read.
fn finish_file(c: &Cursor, b: Builder, seen_both: bool) -> Result<RawMesh, MeshError> {
    if !seen_both {
        return Err(c.err("the file has no $Nodes or no $Elements section (truncated?)"));
    }
    Ok(b.finish(c.path))
}

fn read41(mut c: Cursor, binary: bool) -> Result<RawMesh, MeshError> {
    let mut b = Builder::default();
    // (dim, entity tag) -> physical tags
    let mut ent_phys: HashMap<(u8, i64), Vec<i64>> = HashMap::new();
    let (mut seen_nodes, mut seen_elements) = (false, false);
    while !c.at_end() {
        let sec = c.line_text()?.trim().to_string();
        match sec.as_str() {
            "$PhysicalNames" => physical_names(&mut c, &mut b.groups)?,
            "$Entities" => {
                c.binary = binary;
                let counts = [c.size()?, c.size()?, c.size()?, c.size()?];
                for (dim, &n) in counts.iter().enumerate() {
                    if n > c.b.len() as u64 {
                        return Err(c.err("corrupt entity count"));
                    }
                    for _ in 0..n {
                        let tag = c.int()?;
                        let nbox = if dim == 0 { 3 } else { 6 };
                        for _ in 0..nbox {
                            c.double()?;
                        }
                        let np = c.count(1, "physical tag")?;
                        let mut ph = Vec::with_capacity(np);
                        for _ in 0..np {
                            ph.push(c.int()?.abs());
                        }
                        if dim > 0 {
                            let nb = c.count(1, "bounding entity")?;
                            for _ in 0..nb {
                                c.int()?;
                            }
                        }
                        ent_phys.insert((dim as u8, tag), ph);
                    }
                }
                c.binary = false;
                c.expect("$EndEntities")?;
            }
            "$Nodes" => {
                c.binary = binary;
                let nblocks = c.count(1, "node block")?;
                let _num = c.count(1, "node")?;
                let _min = c.size()?;
                let _max = c.size()?;
                for _ in 0..nblocks {
                    let _dim = c.int()?;
                    let _etag = c.int()?;
                    let param = c.int()?;
                    if param != 0 {
                        return Err(c.err(
                            "parametric nodes are not supported: save without Mesh.SaveParametric",
                        ));
                    }
                    let n = c.count(4, "node")?;
                    let start = b.nodes.len();
                    let mut tags = Vec::with_capacity(n);
                    for _ in 0..n {
                        tags.push(c.size()?);
                    }
                    for tag in tags {
                        let (x, y, z) = (c.double()?, c.double()?, c.double()?);
                        b.add_node(&c, tag, x, y, z)?;
                    }
                    debug_assert_eq!(b.nodes.len(), start + n);
                }
                c.binary = false;
                c.expect("$EndNodes")?;
                seen_nodes = true;
            }
            "$Elements" => {
                c.binary = binary;
                let nblocks = c.count(1, "element block")?;
                let _num = c.count(1, "element")?;
                let _min = c.size()?;
                let _max = c.size()?;
                let mut nt = [0u64; 3];
                for _ in 0..nblocks {
                    let dim = c.int()?;
                    let etag = c.int()?;
                    let ty = c.int()?;
                    let n = c.count(2, "element")?;
                    let phys = ent_phys
                        .get(&(dim.clamp(0, 3) as u8, etag))
                        .cloned()
                        .unwrap_or_default();
                    for _ in 0..n {
                        let tag = c.size()?;
                        let k = nodes_per_type(&c, tag, ty)?;
                        for slot in nt.iter_mut().take(k) {
                            *slot = c.size()?;
                        }
                        b.add_element(&c, tag, ty, &nt[..k], &phys)?;
                    }
                }
                c.binary = false;
                c.expect("$EndElements")?;
                seen_elements = true;
            }
            s => other_section(&mut c, s)?,
        }
    }
    finish_file(&c, b, seen_nodes && seen_elements)
}

fn read22(mut c: Cursor) -> Result<RawMesh, MeshError> {
    let mut b = Builder::default();
    let (mut seen_nodes, mut seen_elements) = (false, false);
    while !c.at_end() {
        let sec = c.line_text()?.trim().to_string();
        match sec.as_str() {
            "$PhysicalNames" => physical_names(&mut c, &mut b.groups)?,
            "$Nodes" => {
                let n = c.count(8, "node")?;
                for _ in 0..n {
                    let tag = c.size()?;
                    let (x, y, z) = (c.double()?, c.double()?, c.double()?);
                    b.add_node(&c, tag, x, y, z)?;
                }
                c.expect("$EndNodes")?;
                seen_nodes = true;
            }
            "$Elements" => {
                let n = c.count(8, "element")?;
                for _ in 0..n {
                    let tag = c.size()?;
                    let ty = c.int()?;
                    let ntags = c.count(2, "tag")?;
                    let mut tags = Vec::with_capacity(ntags);
                    for _ in 0..ntags {
                        tags.push(c.int()?);
                    }
                    let k = nodes_per_type(&c, tag, ty)?;
                    let mut nt = [0u64; 3];
                    for slot in nt.iter_mut().take(k) {
                        *slot = c.size()?;
                    }
                    let phys: Vec<i64> = tags
                        .first()
                        .filter(|&&p| p != 0)
                        .copied()
                        .into_iter()
                        .collect();
                    b.add_element(&c, tag, ty, &nt[..k], &phys)?;
                }
                c.expect("$EndElements")?;
                seen_elements = true;
            }
            s => other_section(&mut c, s)?,
        }
    }
    finish_file(&c, b, seen_nodes && seen_elements)
}
