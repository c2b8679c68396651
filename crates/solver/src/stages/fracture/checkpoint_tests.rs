//! The fracture stage's checkpoint: a stage attached afresh for a resume and restored from a
//! checkpoint taken part-way through the fracture of a Brazilian disc continues bit for bit
//! as the stage that was saved, fed the same positions (forces, reports, joint states, frames,
//! released bonded pairs and their order, the step's breaks, `fractures.csv`); a damaged
//! checkpoint or a CSV file shorter than recorded is an error.

use std::any::Any;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use fdem_time::{Integrator, SecondOrderSystem, State};

use super::{FractureReport, FractureStage};
use crate::checkpoint::{Dec, Enc};
use crate::output::FrameData;
use crate::problem::load::Problem;
use crate::stages::contact::ContactStage;
use crate::stages::system::{
    ForceTerm, SceneSystem, Stage, StageCheckpoint, StageDistribution, StageOutput, StageReport,
    StepEvents,
};

type Shared<T> = Arc<Mutex<T>>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh temporary folder, removed when the test that made it passes (kept for a look
/// when it fails).
pub(super) struct TempDir(PathBuf);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

pub(super) fn temp_dir(tag: &str) -> TempDir {
    let d = std::env::temp_dir().join(format!("fdem-ckfracture-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    TempDir(d)
}

/// `examples/brazilian-disc-fracture.json` on the ring mesh `mesh` of `meshes/`.
pub(super) fn disc(dir: &Path, mesh: &str) -> Problem {
    let text = std::fs::read_to_string(root().join("examples/brazilian-disc-fracture.json"));
    let mut v: serde_json::Value = serde_json::from_str(&text.unwrap()).unwrap();
    let m = root().join("meshes").join(mesh);
    v["bodies"][0]["mesh"] = serde_json::json!(m.display().to_string());
    v["output"]["frames"] = serde_json::json!(0);
    let p = dir.join(format!("{mesh}.json"));
    std::fs::write(&p, v.to_string()).unwrap();
    crate::problem::load::load(&p).unwrap()
}

/// The scene's fracture stage as `crate::stages::attach_to` builds it, and its bonded pairs at
/// set-up.
pub(super) fn stage(
    l: &Problem,
    sys: &SceneSystem,
    out: Option<&Path>,
    resume: bool,
) -> (FractureStage, Vec<[u32; 2]>) {
    let set = l.fracturing.set.clone().unwrap();
    let initial = (l.initial_joint_state.clone())
        .or_else(|| crate::problem::cracks::initial_state(&l.fracturing, &sys.model));
    let (mut stage, bonded) = FractureStage::new(set, &sys.model, out, initial, resume);
    stage.write_properties = l.scene.fracture.as_ref().is_some_and(|f| f.varied_joints());
    (stage, bonded)
}

pub(super) fn system(l: &Problem) -> SceneSystem {
    let alpha = l.scene.damping.mass_proportional;
    SceneSystem::new(l.model.clone(), l.elements.clone(), alpha)
}

/// The first difference between two reports (the release timer, a wall clock, excepted
/// when `timer` is false).
fn report_diff(a: &StageReport, b: &StageReport, timer: bool) -> Option<String> {
    let sums = [
        (a.stored, b.stored),
        (a.fracture, b.fracture),
        (a.switch_loss, b.switch_loss),
    ];
    if sums.iter().any(|(p, q)| p.to_bits() != q.to_bits()) {
        return Some(format!("energies {sums:?}"));
    }
    let (da, db) = (a.details.as_object()?, b.details.as_object()?);
    if da.len() != db.len() {
        return Some("details differ in keys".into());
    }
    for (k, va) in da {
        if k == "bonded_release_s" && !timer {
            continue;
        }
        let vb = &db[k];
        let same = match (va.as_u64(), va.as_f64()) {
            (Some(u), _) => vb.as_u64() == Some(u),
            (None, Some(f)) => vb.as_f64().map(f64::to_bits) == Some(f.to_bits()),
            _ => va == vb,
        };
        if !same {
            return Some(format!("details `{k}`: {va} vs {vb}"));
        }
    }
    None
}

/// The first difference between the joints' committed states and frames.
fn state_diff(
    a: &FractureStage,
    b: &FractureStage,
    x: &[[f64; 2]],
    frames: bool,
) -> Option<String> {
    let (sa, sb) = (a.joint_state()?, b.joint_state()?);
    let bits = |s: &fdem_fracture::JointState, j: usize| {
        let h = &s.history;
        let mut v: Vec<u64> = h.damage[j].iter().map(|d| d.to_bits()).collect();
        v.extend(
            h.shear_secant[j]
                .iter()
                .chain(&h.mode_mix[j])
                .chain(&h.local[j])
                .chain(&h.normal[j])
                .map(|d| d.to_bits()),
        );
        v.extend(
            [
                h.dissipated[j],
                h.stored[j],
                s.stored_at_start[j],
                s.stored_at_break[j],
            ]
            .map(f64::to_bits),
        );
        v
    };
    if let Some(j) = (0..sa.len()).find(|&j| bits(sa, j) != bits(sb, j)) {
        return Some(format!("joint {j}: history differs"));
    }
    let t = |s: &fdem_fracture::JointState| -> Vec<Option<u64>> {
        s.broken_at.iter().map(|b| b.map(f64::to_bits)).collect()
    };
    if sa.intact != sb.intact || t(sa) != t(sb) || sa.n_broken != sb.n_broken {
        return Some("broken joints differ".into());
    }
    let e =
        |s: &fdem_fracture::JointState| [s.stored_initial, s.released_at_break].map(f64::to_bits);
    if e(sa) != e(sb) || sa.generation() != sb.generation() {
        return Some("energy books or commit count differ".into());
    }
    if !frames {
        return None;
    }
    let (mut fa, mut fb) = (FrameData::default(), FrameData::default());
    a.frame_fields(x, &mut fa);
    b.frame_fields(x, &mut fb);
    let (ja, jb) = (fa.joints?, fb.joints?);
    let f64s = |j: &crate::output::JointFrame| -> Vec<u64> {
        let mut v: Vec<u64> = j
            .points
            .as_flattened()
            .iter()
            .map(|p| p.to_bits())
            .collect();
        for a in [
            &j.damage,
            &j.mode_mix,
            &j.time_of_failure,
            &j.opening,
            &j.sliding,
            &j.normal_traction,
            &j.shear_traction,
        ] {
            v.extend(a.iter().map(|p| p.to_bits()));
        }
        v
    };
    if f64s(&ja) != f64s(&jb) || ja.mode != jb.mode || ja.broken != jb.broken {
        return Some("joint frames differ".into());
    }
    if ja.properties != jb.properties {
        return Some("joint properties differ".into());
    }
    None
}

/// The bonded pairs released and not yet taken by the contact stage and the last step's breaks
/// (`ea`, `eb`: what `a` and `b` handed over), and the stages' reports.
fn shared_diff(
    ea: &StepEvents,
    eb: &StepEvents,
    a: &FractureStage,
    b: &FractureStage,
) -> Option<String> {
    if ea.released != eb.released {
        return Some(format!(
            "released pairs: {:?} vs {:?}",
            ea.released, eb.released
        ));
    }
    let breaks = |e: &StepEvents| -> Vec<(u32, u64, u64)> {
        let f = e.fractures.iter();
        f.map(|e| (e.joint.0, e.time.to_bits(), e.energy_released.to_bits()))
            .collect()
    };
    if breaks(ea) != breaks(eb) {
        return Some("the step's breaks differ".into());
    }
    let (ra, rb) = (a.fracture_report(), b.fracture_report());
    let ev = |r: &FractureReport| -> Vec<(u64, u64, u64, String, u64)> {
        let b = f64::to_bits;
        let e = r.events.iter();
        e.map(|e| (b(e.0), b(e.1), b(e.2), e.3.clone(), b(e.4)))
            .collect()
    };
    if (ra.joints, ra.broken) != (rb.joints, rb.broken) || ev(ra) != ev(rb) {
        return Some("reports differ".into());
    }
    None
}

/// What [`Tee`] found.
#[derive(Default)]
struct Log {
    evaluations: u64,
    steps: u64,
    /// Released pairs compared (taken at a force evaluation).
    released: usize,
    /// The first difference found.
    first: Option<String>,
}

/// The saved stage `a` (whose forces drive the system, with the system's step events) and the
/// restored stage `b` (with its own, `events_b`), fed the same `(t, x, v)`; every force,
/// report, joint state, frame, released pair and break compared.
struct Tee {
    a: FractureStage,
    b: FractureStage,
    events_b: StepEvents,
    f: Vec<[f64; 2]>,
    log: Shared<Log>,
}

impl Tee {
    fn note(&self, what: Option<String>) {
        let mut l = self.log.lock().unwrap();
        if l.first.is_none() {
            l.first = what.map(|w| format!("step {} after the restore: {w}", l.steps));
        }
    }
}

impl Stage for Tee {
    fn name(&self) -> &str {
        self.a.name()
    }
}

impl ForceTerm for Tee {
    fn forces(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        events: &mut StepEvents,
    ) {
        // the pairs the contact stage (next in the list) takes from `a`'s events now: `b`'s
        // must be the same (a contact stage would take them too)
        self.note(shared_diff(events, &self.events_b, &self.a, &self.b));
        let n = std::mem::take(&mut self.events_b.released).len();
        self.f.clear();
        self.f.extend_from_slice(f);
        self.a.forces(t, x, v, f, events);
        self.b.forces(t, x, v, &mut self.f, &mut self.events_b);
        let same = f
            .iter()
            .zip(&self.f)
            .all(|(p, q)| p[0].to_bits() == q[0].to_bits() && p[1].to_bits() == q[1].to_bits());
        self.note((!same).then(|| "forces differ".to_string()));
        let mut l = self.log.lock().unwrap();
        l.evaluations += 1;
        l.released += n;
    }

    fn reads_velocities(&self) -> bool {
        self.a.reads_velocities() || self.b.reads_velocities()
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
        self.b.end_of_step(t, x, v, at_last, &mut self.events_b);
        let step = {
            let mut l = self.log.lock().unwrap();
            l.steps += 1;
            l.steps
        };
        let (ra, rb) = (self.a.report(x), self.b.report(x));
        self.note(report_diff(&ra, &rb, false));
        let frames =
            step.is_multiple_of(10) || self.b.joint_state().is_none_or(|s| s.n_broken != 0);
        self.note(state_diff(&self.a, &self.b, x, frames));
        self.note(shared_diff(events, &self.events_b, &self.a, &self.b));
    }
}

impl StageOutput for Tee {
    fn report(&self, x: &[[f64; 2]]) -> StageReport {
        self.a.report(x)
    }

    fn frame_fields(&self, x: &[[f64; 2]], frame: &mut FrameData) {
        self.a.frame_fields(x, frame);
    }

    fn finish(&mut self) {
        self.a.finish();
        self.b.finish();
    }
}

impl StageCheckpoint for Tee {
    fn save(&mut self, e: &mut Enc, events: &StepEvents) -> std::io::Result<()> {
        self.a.save(e, events)
    }

    fn restore(
        &mut self,
        d: &mut Dec,
        events: &mut StepEvents,
    ) -> Result<(), crate::checkpoint::DecodeError> {
        self.a.restore(d, events)
    }

    fn joint_state(&self) -> Option<&fdem_fracture::JointState> {
        self.a.joint_state()
    }
}

impl StageDistribution for Tee {}

/// The broken joints of the fracture stage first in `sys`.
pub(super) fn broken(sys: &SceneSystem) -> usize {
    sys.contributions[0].joint_state().unwrap().n_broken
}

/// The stage of type `T` that `stage` is.
fn downcast<T: Stage>(stage: Box<dyn Stage>) -> Box<T> {
    let any: Box<dyn Any> = stage;
    match any.downcast() {
        Ok(t) => t,
        Err(_) => panic!("a stage of that type"),
    }
}

/// What [`resume_check`] measured.
struct Resumed {
    steps: u64,
    bytes: usize,
    joints: usize,
    broken: usize,
    pending: usize,
    after: Log,
    new_breaks: usize,
    csv_len: u64,
    files: [Vec<u8>; 2],
}

/// Runs the scene of `l` (its fracture and contact stages, central difference at its step)
/// until `stop(broken joints, steps)`, saves the fracture stage, attaches a stage afresh
/// with `resume` (its `fractures.csv` the saved one with a row written after the
/// checkpoint), restores it and checks it equals the saved one (the release timer
/// included); then drives the system `more` steps with both stages fed the same positions
/// through a [`Tee`]. Returns the counts and both `fractures.csv` files.
fn resume_check(l: &Problem, tag: &str, stop: impl Fn(usize, u64) -> bool, more: u64) -> Resumed {
    let dir = temp_dir(tag);
    let mut sys = system(l);
    let (dir_a, dir_b) = (dir.join("a"), dir.join("b"));
    std::fs::create_dir_all(&dir_a).unwrap();
    std::fs::create_dir_all(&dir_b).unwrap();
    let (a, bonded_a) = stage(l, &sys, Some(&dir_a), false);
    let mut contact = ContactStage::new(&l.scene, &sys.model, l.dt, None, u64::MAX, false)
        .expect("a scene with contact");
    contact.bonded = Some(bonded_a.clone());
    sys.events.released_taken = true;
    sys.contributions.push(Box::new(a));
    sys.contributions.push(Box::new(contact));
    let n = sys.model.n_nodes();
    let mut x0 = sys.model.x0.as_flattened().to_vec();
    let mut v0 = sys.model.v0.as_flattened().to_vec();
    for &d in sys.constrained() {
        v0[d] = 0.0;
    }
    sys.prescribe(0.0, &mut x0, &mut v0);
    let mut state = State::new(0.0, x0, v0);
    let mut integ = fdem_time::CentralDifference::new(2 * n);
    let mut steps = 0u64;
    while !stop(broken(&sys), steps) {
        integ.step(&mut sys, &mut state, l.dt);
        steps += 1;
    }
    let pending = sys.events.released.len();
    let at_ckpt = broken(&sys);
    let mut e = Enc::default();
    sys.contributions[0].save(&mut e, &sys.events).unwrap();
    let csv_len = std::fs::metadata(dir_a.join("fractures.csv"))
        .unwrap()
        .len();
    // the resumed run's file: rows written after the checkpoint are cut off
    let mut rows = std::fs::read(dir_a.join("fractures.csv")).unwrap();
    rows.extend_from_slice(b"1.6e-3,0,0,I,0.0,1e-3,7\n");
    std::fs::write(dir_b.join("fractures.csv"), &rows).unwrap();
    let (mut b, bonded_b) = stage(l, &sys, Some(&dir_b), true);
    let mut events_b = StepEvents {
        released_taken: true,
        ..StepEvents::default()
    };
    b.restore(&mut Dec::new(&e.buf), &mut events_b).unwrap();
    let len_b = std::fs::metadata(dir_b.join("fractures.csv"))
        .unwrap()
        .len();
    assert_eq!(len_b, csv_len, "fractures.csv not cut back");
    let x = state.x_nodes();
    let a = *downcast::<FractureStage>(sys.contributions.remove(0));
    // at the restore: everything equal, the release timer included
    assert_eq!(bonded_a, bonded_b, "bonded pairs at set-up differ");
    assert_eq!(report_diff(&a.report(x), &b.report(x), true), None);
    assert_eq!(state_diff(&a, &b, x, true), None);
    // (the step's breaks are not in a checkpoint: a step's commit rewrites them)
    events_b.fractures = sys.events.fractures.clone();
    assert_eq!(shared_diff(&sys.events, &events_b, &a, &b), None);
    let log = Arc::new(Mutex::new(Log::default()));
    let tee = Tee {
        a,
        b,
        events_b,
        f: Vec::with_capacity(n),
        log: log.clone(),
    };
    sys.contributions.insert(0, Box::new(tee));
    for _ in 0..more {
        integ.step(&mut sys, &mut state, l.dt);
    }
    sys.contributions[0].finish();
    let after = std::mem::take(&mut *log.lock().unwrap());
    let tee = downcast::<Tee>(sys.contributions.remove(0));
    let (joints, broken_b) = (
        tee.b.fracture_report().joints,
        tee.b.fracture_report().broken,
    );
    let r = Resumed {
        steps,
        bytes: e.buf.len(),
        joints,
        broken: at_ckpt,
        pending,
        new_breaks: broken_b - at_ckpt,
        after,
        csv_len,
        files: [
            std::fs::read(dir_a.join("fractures.csv")).unwrap(),
            std::fs::read(dir_b.join("fractures.csv")).unwrap(),
        ],
    };
    eprintln!(
        "{tag}: fracture checkpoint at step {}: {} bytes for {joints} joints and {} triangles \
         ({:.1} B/joint, {:.1} B/triangle); {at_ckpt} broken, {pending} released pairs \
         pending; after the restore: {} steps, {} evaluations, {} new breaks, {} released \
         pairs compared; first difference: {:?}",
        r.steps,
        r.bytes,
        l.model.triangles.len(),
        r.bytes as f64 / joints as f64,
        r.bytes as f64 / l.model.triangles.len() as f64,
        r.after.steps,
        r.after.evaluations,
        r.new_breaks,
        r.after.released,
        r.after.first
    );
    r
}

/// The fracturing disc on the coarse ring mesh (384 triangles, 552 joints, platens by
/// contact): run until 6 joints have broken (step 32 378, 1.57 ms; the step's breaks left 2
/// released pairs for the contact stage), checkpoint, restore, 600 more steps
/// ([`resume_check`]). Asserted bit for bit at every evaluation and step: forces, report
/// (but its release timer, a wall clock, equal at the restore), committed joint states,
/// joint frames (every 10th step, and every step once a joint broke), the released pairs and
/// their order, the report with its events and the step's breaks; and `fractures.csv`: the
/// resumed file, longer than at the checkpoint, is cut back and continues as the saved
/// stage's, byte for byte. Measured: 6 more breaks and 152 released pairs after the restore.
#[test]
fn a_restored_fracture_stage_continues_bit_for_bit() {
    let dir = temp_dir("disc");
    let l = disc(&dir, "disc-small.msh");
    let r = resume_check(&l, "resume", |b, s| b >= 6 || s >= 40_000, 600);
    assert_eq!(r.joints, 552);
    // 141.3 bytes per joint measured (the joint histories: 136)
    assert!(r.bytes < 142 * r.joints, "{} bytes", r.bytes);
    assert_eq!(
        r.broken, 6,
        "{} joints broken at step {}",
        r.broken, r.steps
    );
    assert!(r.pending > 0, "no released pairs pending at the checkpoint");
    assert_eq!(r.after.first, None);
    assert_eq!((r.after.steps, r.after.evaluations), (600, 600));
    assert!(
        r.new_breaks >= 4,
        "only {} joints broke after",
        r.new_breaks
    );
    assert!(r.after.released > r.pending, "{} pairs", r.after.released);
    assert!(
        r.files[1].len() as u64 > r.csv_len,
        "no rows after the checkpoint"
    );
    assert!(
        r.files[0] == r.files[1],
        "fractures.csv differs from the saved stage's"
    );
    fdem_figures::record_part(
        82,
        1,
        format!(
            "identical at every evaluation ({} new breaks, {} released pairs after the disc's restore)",
            r.new_breaks, r.after.released
        ),
    );
}

/// The wing-crack block (`examples/wing-crack.json`): its flaw starts broken (the stage
/// adopts a joint state with broken joints and released stars), its joints have drawn
/// strengths (the frames carry each joint's properties). A checkpoint after 100 steps and
/// 100 steps after the restore: everything equal bit for bit as in
/// [`a_restored_fracture_stage_continues_bit_for_bit`].
#[test]
fn a_restored_stage_with_a_pre_existing_crack_continues_bit_for_bit() {
    let dir = temp_dir("wing");
    let text = std::fs::read_to_string(root().join("examples/wing-crack.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let m = root().join("meshes/wing-crack.msh");
    v["bodies"][0]["mesh"] = serde_json::json!(m.display().to_string());
    v["output"]["frames"] = serde_json::json!(0);
    let p = dir.join("wing.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let l = crate::problem::load::load(&p).unwrap();
    let r = resume_check(&l, "resume-wing", |_, s| s >= 100, 100);
    assert!(r.broken > 0, "the flaw's joints start broken");
    assert_eq!(r.after.first, None);
    assert_eq!((r.after.steps, r.after.evaluations), (100, 100));
    assert!(
        r.files[0] == r.files[1],
        "fractures.csv differs from the saved stage's"
    );
    fdem_figures::record_part(
        82,
        2,
        format!(
            "the wing-crack block identical too ({} joints broken at the checkpoint)",
            r.broken
        ),
    );
}

/// A checkpoint cut anywhere, or written for another scene (the 864-triangle disc's stage
/// reading the 384-triangle disc's), is a `DecodeError` that says what is wrong, never a
/// panic; the whole checkpoint restores. Also prints the size of a fresh stage's checkpoint
/// of each disc (bytes per joint and per triangle).
#[test]
fn a_cut_or_foreign_fracture_checkpoint_is_an_error() {
    let dir = temp_dir("damaged");
    let small = disc(&dir, "disc-small.msh");
    let large = disc(&dir, "disc-fracture.msh");
    let (ss, sl) = (system(&small), system(&large));
    let (mut a, _) = stage(&small, &ss, None, false);
    let mut e = Enc::default();
    a.save(&mut e, &StepEvents::default()).unwrap();
    let (mut b, _) = stage(&small, &ss, None, true);
    let mut events = StepEvents::default();
    b.restore(&mut Dec::new(&e.buf), &mut events).unwrap();
    let len = e.buf.len();
    let mut cuts: Vec<usize> = (0..len).step_by(len / 200).collect();
    cuts.extend((len - 40)..len);
    for &cut in &cuts {
        let err = b
            .restore(&mut Dec::new(&e.buf[..cut]), &mut events)
            .unwrap_err();
        assert!(
            err.0.contains("early") || err.0.contains("bytes"),
            "cut {cut}: {err}"
        );
    }
    // flags that disagree: joint 0 broken (not counted); joint 0's bond state 1
    // (softened) while it is undamaged (offsets in a fresh stage's checkpoint: section name
    // and length, joint count, the histories' seven arrays (damage, shear secants, mode
    // indicators: 16 bytes per joint; opening and sliding 32; A sigma 16; stored and
    // dissipated 8 each), the stored energies at the start and at the breaks (8 each), intact
    // flags, times of failure (all `None`), three numbers, then the bond states; each array
    // after its length)
    let nj = c_joints(&small, &e);
    let intact = 24 + 8 + (9 * 8 + (3 * 16 + 32 + 16 + 2 * 8 + 2 * 8) * nj) + 8;
    let bond = intact + nj + (8 + nj) + 32 + 8;
    for (at, value, what) in [
        (intact, 0u8, "0 broken joints counted, 1 flagged"),
        (bond, 1, "bond state 1"),
    ] {
        let mut bad = e.buf.clone();
        assert_eq!(bad[at], 1 - value, "offset {at}");
        bad[at] = value;
        let err = b.restore(&mut Dec::new(&bad), &mut events).unwrap_err();
        assert!(err.0.contains(what), "{err}");
    }
    let (mut c, _) = stage(&large, &sl, None, true);
    let err = c.restore(&mut Dec::new(&e.buf), &mut events).unwrap_err();
    assert!(err.0.contains("joints where the scene has 1260"), "{err}");
    fdem_figures::record_part(
        82,
        3,
        format!(
            "{} cuts, 2 disagreeing flags and another scene's checkpoint refused",
            cuts.len()
        ),
    );
    let mut el = Enc::default();
    c.save(&mut el, &events).unwrap();
    for (l, e) in [(&small, &e), (&large, &el)] {
        let (t, j) = (l.model.triangles.len(), c_joints(l, e));
        eprintln!(
            "fresh fracture checkpoint, {t} triangles, {j} joints: {} bytes ({:.1} B/joint, \
             {:.1} B/triangle)",
            e.buf.len(),
            e.buf.len() as f64 / j as f64,
            e.buf.len() as f64 / t as f64
        );
    }
}

/// The joint count a checkpoint of the scene of `l` records (its first number after the
/// section's name and length).
fn c_joints(_l: &Problem, e: &Enc) -> usize {
    let mut d = Dec::new(&e.buf);
    let _: String = d.get().unwrap();
    let _: u64 = d.get().unwrap();
    d.get().unwrap()
}

/// `fractures.csv` at a restore: shorter than at the checkpoint, or missing, is an error
/// that names the file (a longer one is cut back: [`a_restored_fracture_stage_continues_bit_for_bit`]).
#[test]
fn a_fractures_csv_shorter_than_recorded_or_missing_is_an_error() {
    let dir = temp_dir("csv");
    let l = disc(&dir, "disc-small.msh");
    let sys = system(&l);
    let (mut a, _) = stage(&l, &sys, Some(&dir), false);
    let mut e = Enc::default();
    a.save(&mut e, &StepEvents::default()).unwrap();
    let head = std::fs::read(dir.join("fractures.csv")).unwrap();
    assert!(head.starts_with(b"time,x,y"), "the header is recorded");
    let short = dir.join("short");
    std::fs::create_dir_all(&short).unwrap();
    std::fs::write(short.join("fractures.csv"), &head[..head.len() - 1]).unwrap();
    let (mut b, _) = stage(&l, &sys, Some(&short), true);
    let err = b
        .restore(&mut Dec::new(&e.buf), &mut StepEvents::default())
        .unwrap_err();
    assert!(
        err.0.contains("fractures.csv has") && err.0.contains("fewer"),
        "{err}"
    );
    let missing = dir.join("missing");
    std::fs::create_dir_all(&missing).unwrap();
    let (mut c, _) = stage(&l, &sys, Some(&missing), true);
    let err = c
        .restore(&mut Dec::new(&e.buf), &mut StepEvents::default())
        .unwrap_err();
    assert!(err.0.contains("cannot be opened"), "{err}");
    fdem_figures::record_part(82, 4, "a shorter and a missing fractures.csv refused");
}
