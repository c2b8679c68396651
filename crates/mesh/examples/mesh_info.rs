//! Prints the node, triangle and group counts of mesh files:
//! `cargo run -p fdem-mesh --example mesh_info -- meshes/*.msh`.

fn main() {
    for path in std::env::args().skip(1) {
        match fdem_mesh::read_mesh(&path) {
            Ok(m) => {
                let groups: Vec<String> = m
                    .groups
                    .iter()
                    .map(|g| {
                        let n = match g.dim {
                            0 => g.nodes.len(),
                            1 => g.edges.len(),
                            _ => g.triangles.len(),
                        };
                        format!("{}:{}:{}", g.name, g.dim, n)
                    })
                    .collect();
                println!(
                    "{path} nodes={} triangles={} reoriented={} groups={}",
                    m.n_nodes(),
                    m.n_triangles(),
                    m.reoriented,
                    groups.join(",")
                );
            }
            Err(e) => println!("{path} ERROR {e}"),
        }
    }
}
