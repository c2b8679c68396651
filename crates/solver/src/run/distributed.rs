//! What a distributed run ([`crate::distributed`]) does not do yet, refused before anything
//! is written ([`check`]).

/// Refuses what a distributed run does not do yet, before anything is written: each error
/// names the scene's field and the fix. `size` is the number of ranks.
pub fn check(
    l: &crate::problem::load::Problem,
    size: usize,
) -> Result<(), crate::error::SceneError> {
    use crate::input::scene::{Analysis, TimeStep};
    let file = &l.file;
    let one = "run it as one process (`fdem run SCENE`, or `srun -n 1` in a job): its \
               threads use the machine's cores";
    let bad = |path: &str, what: &str| {
        Err(crate::error::SceneError::invalid(
            file,
            path,
            format!("{what}; this scene cannot be run on {size} processes"),
            one,
        ))
    };
    let tris = l.elements.len();
    if size > tris {
        return Err(crate::error::SceneError::invalid(
            file,
            "bodies",
            format!(
                "{size} processes for {tris} triangles: each process needs a triangle of its own"
            ),
            format!("start at most {tris} processes (`mpirun -np {tris}`)"),
        ));
    }
    if l.scene.analysis == Analysis::Static {
        return bad(
            "analysis",
            "a static analysis is one sparse solve, done by one process",
        );
    }
    if l.scene.analysis == Analysis::Relaxation {
        return bad("analysis", "a relaxation runs on one process");
    }
    if l.scheme != fdem_time::SchemeKind::CentralDifference {
        return bad(
            "integrator.scheme",
            "a distributed run steps with central difference only",
        );
    }
    if l.fluid.is_some() {
        return bad(
            "fluid",
            "the fluid in the crack network is stepped by one process",
        );
    }
    if l.scene.integrator.time_step == TimeStep::Adaptive {
        return bad(
            "integrator.time_step",
            "an adaptive step is not distributed",
        );
    }
    Ok(())
}
