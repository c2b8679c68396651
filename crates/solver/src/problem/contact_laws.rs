//! The contact laws of a scene per pair of bodies, and the contact term of the a-priori
//! frequency bound, from the scene's `"contact"` section and the model.
//!
//! Laws are per pair of **bodies** (each body is usually one material). Forces from the
//! contact crate are per unit thickness, so every penalty is multiplied by the bodies'
//! thickness (the larger of the two; walls use the largest thickness of the scene).
//!
//! The contact term of the frequency bound (docs/time-integration.md, "The stable step of a
//! scene"): `omega_c^2 = max_e 3 p (2 / H_e) l_e (2 / A_e) / rho_e` (a triangle pair of two
//! equal triangles: `3 p (1/H_1 + 1/H_2)` in place of the joint's `p/h`, `H_e` the smallest
//! altitude, `l_e` the longest edge); it covers every edge pressed flat along its whole length.

use fdem_contact::{ContactLaw, ContactLaws};

use crate::input::scene::Scene;
use crate::input::scene::contact::{ContactSection, LawSpec};
use crate::problem::model::Model;

/// The law of `spec` per unit thickness times `thickness`, with Young's modulus `e` for the
/// defaults.
pub(crate) fn contact_law(spec: &LawSpec, e: f64, thickness: f64) -> ContactLaw {
    let p = spec.penalty.unwrap_or(spec.penalty_factor * e);
    ContactLaw {
        penalty: p * thickness,
        mu: spec.friction,
        kt: spec.tangential_penalty.unwrap_or(p) * thickness,
        damping: spec.damping * thickness,
        enabled: true,
    }
}

/// Largest Young's modulus and thickness of each body.
pub(crate) fn body_props(model: &Model, n_bodies: usize) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0f64, 0.0f64); n_bodies];
    for (t, &b) in model.tri_body.iter().enumerate() {
        let (spec, th) = &model.materials[model.tri_material[t] as usize];
        let o = &mut out[b as usize];
        o.0 = o.0.max(spec.young);
        o.1 = o.1.max(*th);
    }
    out
}

/// The contact laws of a scene, per pair of bodies (thickness included).
pub fn laws(section: &ContactSection, scene: &Scene, model: &Model) -> ContactLaws {
    let nb = scene.bodies.len();
    let props = body_props(model, nb);
    let mut laws = ContactLaws::uniform(nb, ContactLaw::disabled());
    for i in 0..nb {
        for j in i..nb {
            let e = props[i].0.max(props[j].0);
            let th = props[i].1.max(props[j].1);
            laws.set(i, j, contact_law(&section.default, e, th));
        }
    }
    // (the pair names were resolved at load, `crate::input::resolve`: every one names a body)
    let index = |name: &str| {
        scene
            .bodies
            .iter()
            .position(|b| b.name.as_deref() == Some(name))
            .unwrap_or(0)
    };
    for p in &section.pairs {
        let (i, j) = (index(&p.bodies[0]), index(&p.bodies[1]));
        let e = props[i].0.max(props[j].0);
        let th = props[i].1.max(props[j].1);
        let law = if p.enabled {
            contact_law(&p.law, e, th)
        } else {
            ContactLaw::disabled()
        };
        laws.set(i, j, law);
    }
    laws
}

/// The contact term of the frequency bound [rad/s] (module docs), 0 without contact.
pub fn omega_contact(scene: &Scene, model: &Model) -> f64 {
    let Some(section) = scene.contact.as_ref().filter(|c| c.enabled) else {
        return 0.0;
    };
    let props = body_props(model, scene.bodies.len());
    let mut p_max = vec![0.0f64; scene.bodies.len()];
    let laws = laws(section, scene, model);
    for (i, pm) in p_max.iter_mut().enumerate() {
        for j in 0..scene.bodies.len() {
            let l = laws.get(i as u32, j as u32);
            if l.enabled {
                *pm = pm.max(l.penalty.max(l.kt) / props[i].1.max(props[j].1));
            }
        }
        for w in &section.walls {
            let l = contact_law(&w.law, props.iter().map(|p| p.0).fold(0.0, f64::max), 1.0);
            *pm = pm.max(l.penalty.max(l.kt));
        }
    }
    let mut w2 = 0.0f64;
    for (e, t) in model.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|i| model.x0[i as usize]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        let len = |p: [f64; 2], q: [f64; 2]| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
        let lmax = len(a, b).max(len(b, c)).max(len(c, a));
        let h_min = 2.0 * area / lmax;
        let rho = model.materials[model.tri_material[e] as usize].0.density
            * model.mass_factor()
            * model.density_factor(e);
        let p = p_max[model.tri_body[e] as usize];
        w2 = w2.max(3.0 * p * (2.0 / h_min) * lmax * (2.0 / area) / rho);
    }
    w2.sqrt()
}
