//! A mutation fuzzer for the MJCF loader and the state API (cargo-fuzz needs a nightly toolchain;
//! this runs on stable): seed models are mutated (numbers replaced by special values or scaled,
//! spans deleted or duplicated, elements nested, text truncated), loaded, and simulated when they
//! load; saved full states are mutated and restored, then stepped. Every input runs under
//! `catch_unwind` and is classified; a panic, a hang or a non-finite value the divergence check
//! misses is a failure.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use sinew::batch::out_of_range;
use sinew::sensors::{self, Sensors};
use sinew::step::state::FlatState;
use sinew::{Model, State};

use super::Rng;

/// An input taking longer than this counts as a hang.
pub const HANG: Duration = Duration::from_secs(10);

/// What a run found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tally {
    /// Model inputs tried.
    pub models: u64,
    /// Of those, models that loaded (and were stepped).
    pub loaded: u64,
    /// Of those, runs that diverged (detected: the state left the finite range).
    pub diverged: u64,
    /// State inputs tried.
    pub states: u64,
    /// Of those, states the API accepted (and stepped).
    pub accepted: u64,
    /// Panics (bugs), with the first few messages.
    pub panics: u64,
    /// Inputs slower than [`HANG`].
    pub hangs: u64,
    /// Non-finite outputs while the state was in range (a silent corruption).
    pub silent_nonfinite: u64,
    /// Examples of failures: input kind and message.
    pub failures: Vec<String>,
}

impl Tally {
    /// Adds another tally.
    pub fn add(&mut self, o: &Tally) {
        self.models += o.models;
        self.loaded += o.loaded;
        self.diverged += o.diverged;
        self.states += o.states;
        self.accepted += o.accepted;
        self.panics += o.panics;
        self.hangs += o.hangs;
        self.silent_nonfinite += o.silent_nonfinite;
        for f in &o.failures {
            if self.failures.len() < 20 {
                self.failures.push(f.clone());
            }
        }
    }
    /// Panics, hangs and silent non-finite values together.
    pub fn failures_total(&self) -> u64 {
        self.panics + self.hangs + self.silent_nonfinite
    }
}

const SPECIAL: &[&str] = &[
    "nan", "inf", "-inf", "1e308", "-1e308", "1e10", "-1e10", "9e9", "0", "-0", "-1", "1e-300", "5e-324", "2147483648",
    "18446744073709551616", "abc", "", "1 2 3 4 5 6 7", "0x10", "1e", ".", "-",
];
const SNIPPETS: &[&str] = &[
    "<body>", "</body>", "<geom size=\"1\"/>", "<joint/>", "<default class=\"x\">", "</default>", "<freejoint/>",
    "<body><joint type=\"ball\"/><geom type=\"box\" size=\"1 1 1\"/></body>", "<camera mode=\"targetbody\" target=\"nope\"/>",
    "<light dir=\"0 0 0\"/>", "<material name=\"geom\"/>", "<texture builtin=\"checker\"/>", "<![CDATA[x]]>", "&amp;", "&bogus;",
    "<?xml version=\"1.0\"?>", "<!-- -->", "\u{0}", "é", "<inertial mass=\"0\" diaginertia=\"0 0 0\"/>",
];

impl Rng {
    /// Uniform in 0..n, 0 when n is 0.
    fn below_or0(&mut self, n: usize) -> usize {
        if n == 0 { 0 } else { self.below(n) }
    }
}

/// Byte offsets of the numbers in `s`.
fn numbers(s: &str) -> Vec<(usize, usize)> {
    let b = s.as_bytes();
    let mut out = vec![];
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() || (b[i] == b'-' && i + 1 < b.len() && b[i + 1].is_ascii_digit()) {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b"eE.-+".contains(&b[i])) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// The nearest char boundary at or before `i`.
fn floor(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// One to four random mutations of `seed`; half the inputs get one change to a number, so that
/// many still load and exercise the step.
pub fn mutate_xml(rng: &mut Rng, seed: &str) -> String {
    let mut s = seed.to_string();
    let (count, kinds) = if rng.below_or0(2) == 0 { (1, 3) } else { (1 + rng.below_or0(4), 8) };
    for _ in 0..count {
        let n = s.len().max(1);
        match rng.below_or0(kinds) {
            0 | 1 => {
                let nums = numbers(&s);
                if let Some(&(a, b)) = nums.get(rng.below_or0(nums.len())) {
                    s.replace_range(a..b, SPECIAL[rng.below_or0(SPECIAL.len())]);
                }
            }
            2 => {
                let nums = numbers(&s);
                if let Some(&(a, b)) = nums.get(rng.below_or0(nums.len()))
                    && let Ok(x) = s[a..b].parse::<f64>()
                {
                    let k = 10f64.powf(rng.uniform(0.0, 1.0) * 12.0 - 6.0) * if rng.below_or0(4) == 0 { -1.0 } else { 1.0 };
                    s.replace_range(a..b, &format!("{}", x * k));
                }
            }
            3 => {
                let a = floor(&s, rng.below_or0(n));
                let b = floor(&s, a + rng.below_or0(200));
                s.replace_range(a..b, "");
            }
            4 => {
                let a = floor(&s, rng.below_or0(n));
                let b = floor(&s, a + rng.below_or0(300));
                let dup = s[a..b].to_string();
                s.insert_str(b, &dup);
            }
            5 => {
                let a = floor(&s, rng.below_or0(n));
                s.insert_str(a, SNIPPETS[rng.below_or0(SNIPPETS.len())]);
            }
            6 => {
                let a = floor(&s, rng.below_or0(n));
                s.truncate(a);
            }
            _ => {
                // deep nesting
                let depth = [10, 150, 250, 3000][rng.below_or0(4)];
                if let Some(a) = s.find("<worldbody>") {
                    let inner = format!("{}<geom size=\"0.1\"/>{}", "<body><joint/>".repeat(depth), "</body>".repeat(depth));
                    s.insert_str(a + "<worldbody>".len(), &inner);
                }
            }
        }
    }
    s
}

/// Steps a model `steps` times from qpos0 with random controls, as the Python layer would
/// (the divergence check after each step), and classifies the outcome into `t`.
fn simulate(m: &Model, steps: usize, rng: &mut Rng, t: &mut Tally, label: &str) {
    let mut s = State::new(m);
    run_steps(m, &mut s, steps, rng, t, label);
}

fn run_steps(m: &Model, s: &mut State, steps: usize, rng: &mut Rng, t: &mut Tally, label: &str) {
    let root = sensors::body_root(m);
    let nb = m.nbody;
    let (mut xpos, mut xmat, mut xipos, mut xvel, mut cfrc, mut qfrc, mut cinert, mut cvel) =
        (vec![0.0; 3 * nb], vec![0.0; 9 * nb], vec![0.0; 3 * nb], vec![0.0; 6 * nb], vec![0.0; 6 * nb], vec![0.0; m.nv], vec![0.0; 10 * nb], vec![0.0; 6 * nb]);
    for k in 0..steps {
        if k % 5 == 0 {
            for (c, r) in s.ctrl.iter_mut().zip(&m.actuator_ctrlrange) {
                *c = r[0] + (r[1] - r[0]) * rng.uniform(0.0, 1.0);
            }
        }
        s.step(m);
        if s.qpos.iter().chain(&s.qvel).any(|&x| out_of_range(x)) || out_of_range(s.time) {
            t.diverged += 1;
            return;
        }
    }
    let out = Sensors { xpos: &mut xpos, xmat: &mut xmat, xipos: &mut xipos, xvel: &mut xvel, cfrc_ext: &mut cfrc, qfrc_constraint: &mut qfrc, cinert: &mut cinert, cvel: &mut cvel };
    sensors::write(m, &root, &mut s.data, &s.qpos, &s.qvel, out);
    let outputs = [&xpos, &xmat, &xipos, &xvel, &cfrc, &qfrc, &cinert, &cvel];
    if outputs.iter().any(|o| o.iter().any(|x| !x.is_finite())) || s.data.dynamics.qacc.iter().any(|x| !x.is_finite()) {
        t.silent_nonfinite += 1;
        t.failures.push(format!("{label}: non-finite outputs at a finite state"));
    }
}

/// Runs one mutated model: load, and simulate `steps` steps if it loads.
pub fn model_input(seed: &str, input_seed: u64, steps: usize) -> Tally {
    let mut t = Tally { models: 1, ..Tally::default() };
    let mut rng = Rng(input_seed);
    let xml = mutate_xml(&mut rng, seed);
    guarded(&mut t, &format!("model input {input_seed}"), || {
        let mut inner = Tally::default();
        if let Ok(m) = Model::from_mjcf(&xml)
            && m.nq > 0
        {
            inner.loaded += 1;
            simulate(&m, steps, &mut rng, &mut inner, &format!("model input {input_seed}"));
        }
        inner
    });
    t
}

/// Runs `f` into `t`, counting a panic or a run slower than [`HANG`] as a failure of `label`.
fn guarded(t: &mut Tally, label: &str, f: impl FnOnce() -> Tally) {
    let start = Instant::now();
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(inner) => t.add(&inner),
        Err(e) => {
            t.panics += 1;
            t.failures.push(format!("{label}: panic: {}", sinew::error::panic_message(&*e)));
        }
    }
    if start.elapsed() > HANG {
        t.hangs += 1;
        t.failures.push(format!("{label}: took {:?}", start.elapsed()));
    }
}

/// A full state of `m` after `steps` random-control steps, flat.
pub fn saved_state(m: &Model, steps: usize, seed: u64) -> Vec<f64> {
    let mut s = State::new(m);
    let mut rng = Rng(seed);
    let mut t = Tally::default();
    run_steps(m, &mut s, steps, &mut rng, &mut t, "seed state");
    let mut v = vec![];
    FlatState::write(s.time, (&s.qpos, &s.qvel, &s.act), &s.ctrl, Some(s.data.full_state()), &mut v);
    v
}

/// Runs one mutated full state: restore (if accepted) and step `steps` steps.
pub fn state_input(m: &Model, saved: &[f64], input_seed: u64, steps: usize) -> Tally {
    let mut t = Tally { states: 1, ..Tally::default() };
    let mut rng = Rng(input_seed);
    let mut v = saved.to_vec();
    let specials = [f64::NAN, f64::INFINITY, -1.0, 0.0, 1.0, 2.0, 1e300, -1e300, 0.5, 4294967296.0, 9.1e15];
    for _ in 0..1 + rng.below_or0(4) {
        let n = v.len();
        if n == 0 {
            break;
        }
        match rng.below_or0(6) {
            0 | 1 => {
                let i = rng.below_or0(n);
                v[i] = specials[rng.below_or0(specials.len())];
            }
            2 => {
                let i = rng.below_or0(n);
                v[i] += (rng.below_or0(5) as f64) - 2.0;
            }
            3 => {
                let (a, b) = (rng.below_or0(n), rng.below_or0(n));
                v.swap(a, b);
            }
            4 => {
                let a = rng.below_or0(n);
                let len = rng.below_or0(12).min(n - a);
                let chunk: Vec<f64> = v[a..a + len].to_vec();
                v.splice(a..a, chunk);
            }
            _ => v.truncate(rng.below_or0(n + 1)),
        }
    }
    guarded(&mut t, &format!("state input {input_seed}"), || {
        let mut inner = Tally::default();
        if let Ok(st) = FlatState::read(m, &v) {
            inner.accepted += 1;
            let mut s = State::new(m);
            s.time = st.time;
            s.qpos.copy_from_slice(st.qpos);
            s.qvel.copy_from_slice(st.qvel);
            s.ctrl.copy_from_slice(st.ctrl);
            let (ff, history) = st.kept();
            s.data.restore(ff, &history);
            run_steps(m, &mut s, steps, &mut rng, &mut inner, &format!("state input {input_seed}"));
        }
        inner
    });
    t
}

/// The seed corpus: gymnasium's MuJoCo model files when `dir` holds them, else (and also) a few
/// models of our own.
pub fn corpus(dir: Option<&std::path::Path>) -> Vec<(String, String)> {
    let mut out = vec![];
    if let Some(d) = dir
        && let Ok(entries) = std::fs::read_dir(d)
    {
        let mut files: Vec<_> = entries.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|x| x == "xml")).collect();
        files.sort();
        for p in files {
            if let Ok(s) = std::fs::read_to_string(&p) {
                out.push((p.file_name().unwrap().to_string_lossy().into_owned(), s));
            }
        }
    }
    out.push((
        "own/chain.xml".into(),
        r#"<mujoco><option timestep="0.005"/><worldbody><geom type="plane" size="5 5 .1"/>
      <body pos="0 0 1"><freejoint/><geom type="box" size=".2 .1 .05"/>
        <body pos=".3 0 0"><joint name="hinge" type="hinge" axis="0 1 0" range="-30 30"/><geom type="capsule" size=".05" fromto="0 0 0 .3 0 0"/>
          <body pos=".3 0 0"><joint type="ball"/><geom type="ellipsoid" size=".1 .05 .05"/></body></body></body>
      <body pos="1 0 .5"><joint type="slide" axis="0 0 1"/><geom type="cylinder" size=".1 .1"/></body>
      </worldbody><actuator><motor joint="hinge" gear="10" ctrlrange="-1 1" ctrllimited="true"/></actuator></mujoco>"#
            .into(),
    ));
    out
}
