//! The contact stage saved after N steps of a run with friction, contact damping and a moving
//! wall with friction, restored into a stage attached afresh (`resume`) for the same scene,
//! then driven alongside the original for M more steps with the same inputs (the original
//! run's positions and velocities): every force, report, frame field, active bound and
//! walls.csv byte is the same. A damaged or foreign section is a `DecodeError`.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use fdem_time::{CentralDifference, Integrator, State};

use crate::checkpoint::pack::{Dec, Enc};
use crate::output::FrameData;
use crate::stages::system::{
    Engaged, ForceTerm, SceneSystem, Stage, StageCheckpoint, StageDistribution, StageOutput,
    StageReport, StepEvents,
};

/// Two discs (R = 25 mm, 384 triangles each) colliding obliquely on a floor that slides and
/// rises under them: friction 0.4 and contact damping between the discs, friction 0.5 and
/// damping at the floor, a small buffer (frequent detections), the energy probe (nodal work
/// books). `top`: a second wall above the discs.
fn scene(dir: &Path, name: &str, bodies: usize, top: bool) -> PathBuf {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/disc-small.msh");
    let mat =
        r#"{ "*": { "young": 10e9, "poisson": 0.25, "density": 2500.0, "plane": "strain" } }"#;
    let body = |name: &str, off: [f64; 2], v: [f64; 2]| {
        format!(
            r#"{{ "name": "{name}", "mesh": {mesh:?}, "materials": {mat}, "offset": [{}, {}], "initial_velocity": [{}, {}] }}"#,
            off[0], off[1], v[0], v[1]
        )
    };
    let mut b = vec![body("left", [-0.02502, 0.0], [3.0, -1.0])];
    if bodies > 1 {
        b.push(body("right", [0.02502, 0.004], [-1.0, 0.0]));
    }
    let law = r#""law": { "friction": 0.5, "damping": 5e6 }"#;
    let mut walls = vec![format!(
        r#"{{ "name": "floor", "point": [0.0, -0.02502], "normal": [0.0, 1.0], "velocity": [0.5, 0.5], {law} }}"#
    )];
    if top {
        walls.push(format!(
            r#"{{ "name": "top", "point": [0.0, 0.04], "normal": [0.0, -1.0], {law} }}"#
        ));
    }
    let text = format!(
        r#"{{
  "title": "contact checkpoint test",
  "bodies": [{}],
  "contact": {{ "buffer": 2e-4, "default": {{ "friction": 0.4, "damping": 5e6 }}, "walls": [{}] }},
  "integrator": {{ "scheme": "central-difference", "time_step": "auto", "safety": 0.9 }},
  "duration": 1e-3,
  "histories": {{ "probes": [ "energy" ] }}
}}"#,
        b.join(", "),
        walls.join(", ")
    );
    let file = dir.join(name);
    std::fs::write(&file, text).unwrap();
    file
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fdem-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The scene's system with its stages attached (the contact stage alone: no fracture), its
/// initial state and step.
fn system(file: &Path, out: Option<&Path>, resume: bool) -> (SceneSystem, State, f64) {
    let l = crate::problem::load::load(file).expect("scene loads");
    let mut sys = SceneSystem::new(l.model.clone(), l.elements.clone(), 0.0);
    crate::stages::attach_to(&l, &mut sys, l.dt, out, 1, resume).unwrap();
    assert_eq!(sys.contributions.len(), 1, "the contact stage");
    let state = State::new(
        0.0,
        l.model.x0.as_flattened().to_vec(),
        l.model.v0.as_flattened().to_vec(),
    );
    (sys, state, l.dt)
}

fn bits(v: &[[f64; 2]]) -> Vec<u64> {
    v.iter().flatten().map(|x| x.to_bits()).collect()
}

/// Everything a report gives, exactly (serde_json writes each f64 in its shortest exact form).
fn report_text(r: &StageReport) -> String {
    let n = [
        r.stored,
        r.friction,
        r.contact_damping,
        r.fracture,
        r.switch_loss,
        r.contact_residual,
        r.wall_work,
    ]
    .map(f64::to_bits);
    format!("{n:?} {:?} {}", r.error, r.details)
}

/// The original stage `a` and the restored one `b`, driven with the same calls: each call's
/// results are compared bit for bit.
struct Twin {
    a: Box<dyn Stage>,
    b: Box<dyn Stage>,
    /// End-of-step comparisons made.
    checks: Arc<Mutex<u64>>,
}

impl Twin {
    fn compare(&mut self, t: f64, x: &[[f64; 2]]) {
        let (ra, rb) = (self.a.report(x), self.b.report(x));
        assert_eq!(report_text(&ra), report_text(&rb), "t = {t:e}: report");
        let (mut fa, mut fb) = (FrameData::default(), FrameData::default());
        self.a.frame_fields(x, &mut fa);
        self.b.frame_fields(x, &mut fb);
        assert_eq!(fa.extra_point_vectors.len(), 1);
        for ((na, va), (nb, vb)) in fa.extra_point_vectors.iter().zip(&fb.extra_point_vectors) {
            assert_eq!((na, bits(va)), (nb, bits(vb)), "t = {t:e}: frame {na}");
        }
        for ((na, va), (nb, vb)) in fa.extra_cell_scalars.iter().zip(&fb.extra_cell_scalars) {
            let (ba, bb): (Vec<u64>, Vec<u64>) = (
                va.iter().map(|v| v.to_bits()).collect(),
                vb.iter().map(|v| v.to_bits()).collect(),
            );
            assert_eq!((na, ba), (nb, bb), "t = {t:e}: frame {na}");
        }
        let (wa, wb) = (
            self.a.active_frequency_bound(x, Engaged::LastEvaluation),
            self.b.active_frequency_bound(x, Engaged::LastEvaluation),
        );
        assert_eq!(wa.map(f64::to_bits), wb.map(f64::to_bits), "t = {t:e}");
        assert_eq!(self.a.error(), self.b.error());
        *self.checks.lock().unwrap() += 1;
    }
}

impl Stage for Twin {
    fn name(&self) -> &str {
        "twin"
    }
}

/// (No fracture stage: `events` carries nothing, and each stage gets the system's.)
impl ForceTerm for Twin {
    fn forces(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        events: &mut StepEvents,
    ) {
        let mut fb = f.to_vec();
        self.a.forces(t, x, v, f, events);
        self.b.forces(t, x, v, &mut fb, events);
        assert_eq!(bits(f), bits(&fb), "t = {t:e}: forces");
    }
    fn end_of_step(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        at_last: bool,
        events: &mut StepEvents,
    ) {
        self.a.end_of_step(t, x, v, at_last, events);
        self.b.end_of_step(t, x, v, at_last, events);
        self.compare(t, x);
    }
    fn reads_velocities(&self) -> bool {
        self.a.reads_velocities()
    }
}

impl StageOutput for Twin {
    fn report(&self, x: &[[f64; 2]]) -> StageReport {
        self.a.report(x)
    }
    fn finish(&mut self) {
        self.a.finish();
        self.b.finish();
    }
}

impl StageCheckpoint for Twin {
    fn save(&mut self, _e: &mut Enc, _events: &StepEvents) -> std::io::Result<()> {
        Ok(())
    }
    fn restore(
        &mut self,
        _d: &mut Dec,
        _events: &mut StepEvents,
    ) -> Result<(), crate::checkpoint::pack::DecodeError> {
        Ok(())
    }
}

impl StageDistribution for Twin {}

/// A number of the stage's report details.
fn detail(sys: &SceneSystem, x: &[f64], key: &str) -> f64 {
    let r = sys.contributions[0].report(x.as_chunks::<2>().0);
    r.details[key].as_f64().unwrap_or_else(|| panic!("{key}"))
}

#[test]
fn a_restored_stage_continues_bit_for_bit() {
    let dir = temp_dir("contact-checkpoint");
    let (da, db) = (dir.join("a"), dir.join("b"));
    std::fs::create_dir_all(&da).unwrap();
    std::fs::create_dir_all(&db).unwrap();
    let file = scene(&dir, "scene.json", 2, false);
    let (mut sa, mut state, dt) = system(&file, Some(&da), false);
    let mut cd = CentralDifference::new(state.x.len());
    let (n, m) = (300, 1500);
    for _ in 0..n {
        cd.step(&mut sa, &mut state, dt);
    }
    let keys = [
        "detections",
        "friction_dissipated",
        "damping_dissipated",
        "wall_work",
        "node_work",
    ];
    let before = keys.map(|k| detail(&sa, &state.x, k));
    let mut e = Enc::default();
    sa.contributions[0].save(&mut e, &sa.events).unwrap();
    // The resumed run's walls.csv: the original's at the save, plus rows written after it
    // (cut back by the restore).
    let mut csv = std::fs::read(da.join("walls.csv")).unwrap();
    csv.extend_from_slice(b"1.0e0,rows of the run after the checkpoint\n");
    std::fs::write(db.join("walls.csv"), csv).unwrap();
    let (mut sb, _, _) = system(&file, Some(&db), true);
    let mut d = Dec::new(&e.buf);
    sb.contributions[0]
        .restore(&mut d, &mut sb.events)
        .expect("restores");
    assert_eq!(d.remaining(), 0);
    let checks = Arc::new(Mutex::new(0));
    let twin = Twin {
        a: sa.contributions.remove(0),
        b: sb.contributions.remove(0),
        checks: checks.clone(),
    };
    sa.contributions.push(Box::new(twin));
    for _ in 0..m {
        cd.step(&mut sa, &mut state, dt);
    }
    sa.contributions[0].finish();
    assert_eq!(*checks.lock().unwrap(), m, "one comparison per step");
    let after = keys.map(|k| detail(&sa, &state.x, k));
    let (wa, wb) = (
        std::fs::read(da.join("walls.csv")).unwrap(),
        std::fs::read(db.join("walls.csv")).unwrap(),
    );
    assert!(wa == wb, "walls.csv differs");
    let n_tris = sa.model.triangles.len();
    eprintln!(
        "dt = {dt:e} s; {keys:?} at the save {before:?}, {m} steps later {after:?}; \
         contact section {} bytes = {:.1} per triangle ({n_tris} triangles)",
        e.buf.len(),
        e.buf.len() as f64 / n_tris as f64
    );
    // What the case is meant to cover happened after the restore: detections, slip,
    // damping, wall work (the floor moves under load).
    for k in 0..keys.len() - 1 {
        assert!(
            after[k] > before[k],
            "{}: {} -> {}",
            keys[k],
            before[k],
            after[k]
        );
    }
    assert!(before[1] > 0.0, "friction slip before the save");
    fdem_figures::record_part(
        83,
        2,
        format!(
            "stage identical over {m} steps ({} detections after the restore)",
            after[0] - before[0]
        ),
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_damaged_or_foreign_contact_section_is_an_error() {
    let dir = temp_dir("contact-checkpoint-damaged");
    let file = scene(&dir, "scene.json", 2, false);
    let (mut sa, mut state, dt) = system(&file, None, false);
    let mut cd = CentralDifference::new(state.x.len());
    for _ in 0..150 {
        cd.step(&mut sa, &mut state, dt);
    }
    let mut e = Enc::default();
    sa.contributions[0].save(&mut e, &sa.events).unwrap();
    let buf = &e.buf;
    let fresh = |file: &Path| system(file, None, true).0;
    // the whole section restores; every cut of it is an error
    assert!(
        fresh(&file).contributions[0]
            .restore(&mut Dec::new(buf), &mut StepEvents::default())
            .is_ok()
    );
    let step = (buf.len() / 400).max(1);
    let mut cuts = 0;
    for cut in (0..buf.len())
        .step_by(step)
        .chain(buf.len() - 40..buf.len())
    {
        let mut s = fresh(&file);
        let r = s.contributions[0].restore(&mut Dec::new(&buf[..cut]), &mut s.events);
        assert!(r.is_err(), "cut at {cut} of {}", buf.len());
        cuts += 1;
    }
    // a section of another scene: one disc (other node and triangle counts), two walls
    for (name, bodies, top, what) in [
        ("one.json", 1, false, "nodes"),
        ("walls.json", 2, true, "2 values where the scene has 1"),
    ] {
        let other = scene(&dir, name, bodies, top);
        let (mut so, mut st, dt) = system(&other, None, false);
        let mut cd = CentralDifference::new(st.x.len());
        for _ in 0..150 {
            cd.step(&mut so, &mut st, dt);
        }
        let mut eo = Enc::default();
        so.contributions[0].save(&mut eo, &so.events).unwrap();
        let err = fresh(&file).contributions[0]
            .restore(&mut Dec::new(&eo.buf), &mut StepEvents::default())
            .expect_err(name);
        assert!(err.0.contains(what), "{name}: {err}");
    }
    fdem_figures::record_part(
        83,
        3,
        format!("{cuts} cuts and 2 other scenes' sections refused"),
    );
    let _ = std::fs::remove_dir_all(&dir);
}
