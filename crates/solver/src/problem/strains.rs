//! The strain estimate of each load, velocity and gravity of a scene on the body it acts on
//! ([`input_strains`]): what a run's diagnosis names as the likely cause of an instability,
//! and what the static range check compares with the floating-point range.

use crate::input::scene::{BoundaryCondition, Scene};
use crate::problem::model::{LARGE_STRAIN, Model};

/// One input's estimated strain on the body it acts on.
#[derive(Debug, Clone)]
pub struct InputStrain {
    /// JSON path of the input (e.g. `boundary_conditions[1]`).
    pub path: String,
    /// What it is, in words, with its magnitude.
    pub what: String,
    /// The strain estimate (dimensionless).
    pub strain: f64,
}

/// A body's scale for the estimates: smallest Young's modulus [Pa], largest density
/// [kg/m^3], smallest thickness [m], smaller and larger bounding-box sides [m].
#[derive(Debug, Clone, Copy)]
struct BodyScale {
    young: f64,
    density: f64,
    thickness: f64,
    h_small: f64,
    h_large: f64,
}

fn body_scales(model: &Model) -> Vec<BodyScale> {
    let nb = model.body_nodes.len();
    let mut s = vec![
        BodyScale {
            young: f64::INFINITY,
            density: 0.0,
            thickness: f64::INFINITY,
            h_small: 0.0,
            h_large: 0.0,
        };
        nb
    ];
    for (t, &b) in model.tri_body.iter().enumerate() {
        let Some(bs) = s.get_mut(b as usize) else {
            continue;
        };
        if let Some((m, _)) = model.materials.get(model.tri_material[t] as usize) {
            bs.young = bs.young.min(m.young);
            bs.density = bs.density.max(m.density);
        }
        bs.thickness = bs.thickness.min(model.tri_thickness[t]);
    }
    for (b, r) in model.body_nodes.iter().enumerate() {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &model.x0[r.start as usize..r.end as usize] {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
        s[b].h_large = w.max(h);
        s[b].h_small = if w.min(h) > 0.0 { w.min(h) } else { w.max(h) };
    }
    s
}

fn body_of_node(model: &Model, node: u32) -> usize {
    model
        .body_nodes
        .iter()
        .position(|r| r.contains(&node))
        .unwrap_or(0)
}

/// The name of body `b` for messages: `'name'` or `bodies[b]`.
pub(crate) fn body_name(scene: &Scene, b: usize) -> String {
    match scene.bodies.get(b).and_then(|x| x.name.as_deref()) {
        Some(n) => format!("'{}'", fdem_mesh::excerpt(n)),
        None => format!("bodies[{b}]"),
    }
}

/// The strain estimate of every load, velocity and gravity of the scene, largest first.
pub fn input_strains(scene: &Scene, model: &Model) -> Vec<InputStrain> {
    let scales = body_scales(model);
    let mut out = Vec::new();
    let scale = |b: usize| scales.get(b).copied();
    // Loads: one model load per load condition, in scene order.
    let mut loads = model.loads.iter();
    for (i, bc) in scene.boundary_conditions.iter().enumerate() {
        let (kind, group) = match bc {
            BoundaryCondition::Pressure(p) => ("pressure", &p.group),
            BoundaryCondition::Traction(p) => ("traction", &p.group),
            BoundaryCondition::PointLoad(p) => ("point load", &p.group),
            BoundaryCondition::Velocity(v) => {
                let peak = v.history.as_ref().map_or(1.0, |h| {
                    crate::problem::time_function::History::new(h).max_abs()
                });
                let speed = peak * v.x.unwrap_or(0.0).hypot(v.y.unwrap_or(0.0));
                let b = model
                    .groups
                    .iter()
                    .find(|(b, name, _)| {
                        *name == v.group
                            && v.body.as_ref().is_none_or(|want| {
                                scene.bodies.get(*b as usize).and_then(|x| x.name.as_ref())
                                    == Some(want)
                            })
                    })
                    .map_or(0, |(b, _, _)| *b as usize);
                if let Some(s) = scale(b) {
                    let c = (s.young / s.density).sqrt();
                    let what = format!(
                        "the prescribed velocity on '{}' ({speed:.3e} m/s, against the wave speed {c:.3e} m/s of body {})",
                        fdem_mesh::excerpt(&v.group),
                        body_name(scene, b)
                    );
                    // a velocity as written within range, made too large by the loading
                    // rate (which multiplied it): the rate is the input at fault
                    let rate = scene.loading.as_ref().map_or(1.0, |l| l.rate);
                    let (path, what) = if rate > 1.0 && speed / rate / c <= LARGE_STRAIN {
                        (
                            "loading.rate".to_string(),
                            format!("the loading rate {rate:.3e} makes {what}"),
                        )
                    } else {
                        (format!("boundary_conditions[{i}]"), what)
                    };
                    out.push(InputStrain {
                        path,
                        what,
                        strain: speed / c,
                    });
                }
                continue;
            }
            BoundaryCondition::Fixed(_) | BoundaryCondition::Displacement(_) => continue,
        };
        let Some(load) = loads.next() else { break };
        let total: f64 = {
            let mut per_node = std::collections::BTreeMap::<u32, [f64; 2]>::new();
            for &(d, f) in &load.forces {
                per_node.entry(d / 2).or_default()[(d % 2) as usize] += f;
            }
            let peak = load.history.as_ref().map_or(1.0, |h| h.max_abs());
            peak * per_node.values().map(|f| f[0].hypot(f[1])).sum::<f64>()
        };
        let b = load
            .forces
            .first()
            .map_or(0, |&(d, _)| body_of_node(model, d / 2));
        if let Some(s) = scale(b) {
            let stiff = s.young * s.thickness * s.h_small;
            out.push(InputStrain {
                path: format!("boundary_conditions[{i}]"),
                what: format!(
                    "the {kind} on '{}' ({total:.3e} N in total, against E t h = {stiff:.3e} N of body {})",
                    fdem_mesh::excerpt(group),
                    body_name(scene, b)
                ),
                strain: total / stiff,
            });
        }
    }
    for (b, body) in scene.bodies.iter().enumerate() {
        let speed = body.initial_velocity[0].hypot(body.initial_velocity[1]);
        if let (true, Some(s)) = (speed > 0.0, scale(b)) {
            let c = (s.young / s.density).sqrt();
            out.push(InputStrain {
                path: format!("bodies[{b}].initial_velocity"),
                what: format!(
                    "the initial velocity of body {} ({speed:.3e} m/s, against its wave speed {c:.3e} m/s)",
                    body_name(scene, b)
                ),
                strain: speed / c,
            });
        }
    }
    if let Some(g) = scene.gravity {
        let g = g[0].hypot(g[1]);
        for (b, s) in scales.iter().enumerate() {
            out.push(InputStrain {
                path: "gravity".into(),
                what: format!(
                    "gravity ({g:.3e} m/s^2 on body {}: rho g H / E)",
                    body_name(scene, b)
                ),
                strain: s.density * g * s.h_large / s.young,
            });
        }
    }
    out.retain(|s| !s.strain.is_nan());
    out.sort_by(|a, b| b.strain.total_cmp(&a.strain));
    out
}

/// The fastest prescribed speed of a scene, supports and enabled walls, each times the
/// largest factor of its history [m/s], and the largest prescribed displacement [m]
/// (`loading.rate` is in them).
pub fn fastest_loading(scene: &Scene, model: &Model) -> (f64, f64) {
    let (mut v, mut d) = (0.0f64, 0.0f64);
    for p in &model.prescribed {
        let f = p.history.as_ref().map_or(1.0, |h| h.max_abs());
        if p.displacement {
            d = d.max((p.velocity * f).abs());
        } else {
            v = v.max((p.velocity * f).abs());
        }
    }
    let walls = scene
        .contact
        .iter()
        .filter(|c| c.enabled)
        .flat_map(|c| &c.walls);
    for w in walls {
        let f = w.history.as_ref().map_or(1.0, |h| {
            crate::problem::time_function::History::new(h).max_abs()
        });
        v = v.max(w.velocity[0].hypot(w.velocity[1]) * f);
    }
    (v, d)
}
