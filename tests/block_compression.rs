//! Uniaxial compression of a block (examples/block-compression.json): a homogeneous field,
//! which constant-strain triangles represent exactly on any mesh (the patch test at the scale
//! of a whole specimen). Top displaced by u = v T = -1e-4 m over H = 0.1 m, lateral sides
//! free: reaction E eps W t = 75 kN and lateral expansion nu eps W = 1.25e-5 m, to 1e-9.

use crate::common;

#[test]
fn block_reaction_and_lateral_expansion_are_exact() {
    let scene = common::edited_example("block-compression.json", "block", |_| {});
    let (_, out) = common::run(&scene);
    let (h, rows) = common::histories(&out);
    let ry = common::column(&h, &rows, "reaction_y[top]")[0];
    let ux = common::column(&h, &rows, "u_x[right]")[0];
    let (e, nu, eps, w, t) = (30e9, 0.25, 1e-3, 0.05, 0.05);
    let r_exact = -e * eps * w * t;
    eprintln!(
        "block: reaction {ry:.9e} N (exact {r_exact:e}), lateral {ux:.9e} m (exact {:e})",
        nu * eps * w
    );
    assert!((ry / r_exact - 1.0).abs() < 1e-9, "reaction {ry}");
    assert!((ux / (nu * eps * w) - 1.0).abs() < 1e-9, "lateral {ux}");
    let worst = (ry / r_exact - 1.0)
        .abs()
        .max((ux / (nu * eps * w) - 1.0).abs());
    fdem_figures::record(11, format!("largest relative error {worst:.1e}"));
}
