//! A rig described as data (`rigs/*.json` or a campaign's `"rig"`), compiled
//! once and run through the [`CompiledRig`] interface like any model. Its
//! stability bound is in `stability.rs`, its linearisation in `linearise.rs`.

use std::ops::ControlFlow;

use super::Linearised;
use crate::base::{Drive, MeasuredSample, ParamInfo, Report, Sample};
use crate::base::{SampleGrid, walk_grid};
use crate::compile::Arith;
use crate::compile::back::native::{Native, NativeSlot};
use crate::compile::{EventStepper, GpuRig, LANES, LaneCode, LaneRunner, Lowered, Tape, lower};
use crate::rig::RigError;
use crate::rig::desc::{Coef, DamperLaw, RigDesc};

pub use super::stability::SUBLINEAR_FLOOR;

/// A compiled rig. Built once per job and shared (`Arc`) by the campaign, its
/// problem and its evaluators.
#[derive(Debug)]
pub struct CompiledRig {
    pub(super) id: String,
    pub(super) params: Vec<ParamInfo>,
    pub(super) states: Vec<String>,
    outputs: Vec<(String, String)>,
    /// The description it was compiled from.
    pub desc: RigDesc,
    /// The compiled programs, one per drive mode.
    pub lowered: Lowered,
    pub(super) tapes: Vec<Tape>,
    /// Each tape in the lane ensemble's register form.
    lane_code: Vec<LaneCode>,
    /// Each lane code's native build, made once it pays.
    native: Vec<NativeSlot>,
    /// Each lane code's f32 build, made when first asked for.
    native_f32: Vec<NativeSlot>,
    /// Each program prepared for the GPU kernels (`None`: it cannot run there).
    gpu: Vec<Option<std::sync::Arc<GpuRig>>>,
    /// Each program's fitness variant, where it skips switches that can no
    /// longer reach the measured output ([`crate::compile::analysis::liveness`]); `None`
    /// where it would skip none.
    fitness: Vec<Option<FitnessVariant>>,
    /// The file it was compiled from, for messages.
    file: String,
    /// Per output `k > 0`, the rig compiled to score that output
    /// ([`CompiledRig::scoring`]), once asked for.
    scoring: Vec<std::sync::OnceLock<std::sync::Arc<CompiledRig>>>,
}

/// A program's fitness variant and its lane code and native builds (its
/// graph, and so its tape, is the program's own).
#[derive(Debug)]
struct FitnessVariant {
    program: crate::compile::Program,
    lane_code: LaneCode,
    native: NativeSlot,
    native_f32: NativeSlot,
}

/// What one program's lane runs read: the program, its tape and lane code.
type LaneParts<'a> = (&'a crate::compile::Program, &'a Tape, &'a LaneCode);

/// How a group of lane runs reports ([`CompiledRig::run_lanes`]).
enum Observe<'a> {
    /// Each run at each sample, as [`crate::model::CompiledRig::simulate_many`].
    Each(
        Report,
        &'a mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ),
    /// Output 0 of the group at each sample, as [`crate::model::CompiledRig::simulate_measured`].
    Measured(&'a mut dyn FnMut(&MeasuredSample<'_>, &mut u64)),
}

/// Whether the drive prescribes node `k`'s motion in `prog`: its
/// displacement slot's derivative is then the constant 0, so it is not a
/// degree of freedom and the stability bound has no row for it.
pub(super) fn prescribed(prog: &crate::compile::Program, k: usize) -> bool {
    matches!(
        prog.graph.ops[prog.deriv[k] as usize],
        crate::compile::Op::Const(_)
    )
}

impl CompiledRig {
    /// Index of parameter `name`, which validation has checked exists.
    pub(super) fn param_index(&self, name: &str) -> usize {
        self.params
            .iter()
            .position(|p| p.name == name)
            .expect("a parameter validation checked")
    }

    /// Compiles `desc` (read from `file`, for messages).
    pub fn new(desc: RigDesc, file: &str) -> Result<Self, RigError> {
        let lowered = lower(&desc, file)?;
        let params: Vec<ParamInfo> = desc
            .params
            .iter()
            .map(|p| ParamInfo {
                name: p.name.clone(),
                unit: p.unit.clone(),
                doc: p.doc.clone(),
                scope: p.scope,
                default: p.default,
                scale: p.scale,
            })
            .collect();
        let states: Vec<String> = lowered.states.clone();
        let outputs: Vec<(String, String)> = desc
            .outputs
            .iter()
            .map(|o| (o.name.clone(), o.unit.clone()))
            .collect();
        let desc_outputs = desc.outputs.len().saturating_sub(1);
        let tapes: Vec<Tape> = lowered.programs.iter().map(Tape::new).collect();
        let lane_code = lowered
            .programs
            .iter()
            .zip(&tapes)
            .map(|(p, t)| LaneCode::new(p, t))
            .collect();
        let variants: Vec<Option<crate::compile::Program>> = lowered
            .programs
            .iter()
            .map(crate::compile::analysis::liveness::skipping_variant)
            .collect();
        let gpu = lowered
            .programs
            .iter()
            .zip(&variants)
            .map(|(p, v)| {
                GpuRig::with_fitness(p, v.clone())
                    .ok()
                    .map(std::sync::Arc::new)
            })
            .collect();
        let fitness = variants
            .into_iter()
            .zip(&tapes)
            .map(|(v, t)| {
                v.map(|v| FitnessVariant {
                    lane_code: LaneCode::new(&v, t),
                    program: v,
                    native: NativeSlot::default(),
                    native_f32: NativeSlot::default(),
                })
            })
            .collect();
        Ok(Self {
            id: desc.id.clone(),
            params,
            states,
            outputs,
            desc,
            lowered,
            native: std::iter::repeat_with(NativeSlot::default)
                .take(tapes.len())
                .collect(),
            native_f32: std::iter::repeat_with(NativeSlot::default)
                .take(tapes.len())
                .collect(),
            tapes,
            lane_code,
            gpu,
            fitness,
            file: file.to_string(),
            scoring: std::iter::repeat_with(std::sync::OnceLock::new)
                .take(desc_outputs)
                .collect(),
        })
    }

    /// The rig compiled to score output `k` (`k > 0`): the same rig with that
    /// output moved first, so that every path's fitness (the GPU kernels, the
    /// lanes, the native code), which scores output 0, scores it. Its
    /// histories list the outputs in that order ([`Self::scoring_order`]).
    /// Compiled once, when first asked for; a channel of a campaign asks when
    /// the campaign is read, so that any error shows there.
    pub fn scoring(&self, k: usize) -> Result<std::sync::Arc<CompiledRig>, RigError> {
        assert!(k > 0 && k < self.outputs.len(), "output {k} to score");
        let slot = &self.scoring[k - 1];
        if let Some(rig) = slot.get() {
            return Ok(rig.clone());
        }
        let mut desc = self.desc.clone();
        let out = desc.outputs.remove(k);
        desc.outputs.insert(0, out);
        let rig = std::sync::Arc::new(Self::new(desc, &self.file)?);
        Ok(slot.get_or_init(|| rig).clone())
    }

    /// Where output `o` stands in the outputs of [`Self::scoring`]`(k)`.
    pub fn scoring_order(k: usize, o: usize) -> usize {
        match o {
            _ if o == k => 0,
            _ if o < k => o + 1,
            _ => o,
        }
    }

    /// Compiles `desc` to share between the campaign, its problem and its
    /// evaluators.
    pub fn shared(desc: RigDesc, file: &str) -> Result<std::sync::Arc<Self>, RigError> {
        Ok(std::sync::Arc::new(Self::new(desc, file)?))
    }

    /// The native builds runs of `drive` use, in the order a job wants
    /// them: the fitness runs' (where they have a variant of their own),
    /// then the full program's (histories, the polish); none where the
    /// drive has no lane program.
    pub fn native_builds(&self, drive: &Drive) -> Vec<(&NativeSlot, &LaneCode)> {
        let Some(i) = self.program_for(drive) else {
            return vec![];
        };
        let full = (&self.native[i], &self.lane_code[i]);
        match &self.fitness[i] {
            Some(f) => vec![(&f.native, &f.lane_code), full],
            None => vec![full],
        }
    }

    /// Builds now the f64 native code the fitness runs of `drive` use, rather
    /// than once their work has made it pay ([`NativeSlot::get`]): for a timed
    /// trial, which should measure the path the job will run. Nothing where
    /// the drive has no lane program or `RIGFIT_NATIVE=off`.
    pub fn prepare_native(&self, drive: &Drive) {
        if let Some((slot, code)) = self.native_builds(drive).first() {
            slot.now(code, Arith::F64);
        }
    }

    /// The f64 native build of `code` in `slot` for running `params` on
    /// `grid`, once its work so far makes it pay ([`NativeSlot::get`]).
    fn native_for(
        slot: &NativeSlot,
        code: &LaneCode,
        params: &[&[f64]],
        grid: &SampleGrid,
    ) -> Option<std::sync::Arc<Native>> {
        let work = (params.len() * grid.total_steps()) as u64;
        slot.get(code, work)
    }

    /// Program `i`'s parts for lane runs.
    fn lane_parts(&self, i: usize) -> LaneParts<'_> {
        (
            &self.lowered.programs[i],
            &self.tapes[i],
            &self.lane_code[i],
        )
    }

    /// `params` run by a program's lane ensemble (`parts`), natively where
    /// `native` is its build, in groups of [`LANES`].
    fn run_lanes(
        &self,
        parts: LaneParts<'_>,
        drive: &Drive,
        params: &[&[f64]],
        grid: &SampleGrid,
        native: Option<&Native>,
        mut observe: Observe<'_>,
    ) {
        let force = drive.force_table();
        let (program, tape, code) = parts;
        for (c, chunk) in params.chunks(LANES).enumerate() {
            let mut runner = LaneRunner::new(program, tape, code, chunk, force);
            if let Some(n) = native {
                runner = runner.with_native(n);
            }
            let mut runner = runner.numbered_from(c * LANES);
            match &mut observe {
                Observe::Each(report, f) => runner.run(grid, *report, *f),
                Observe::Measured(f) => runner.run_measured(grid, *f),
            }
        }
    }

    /// Index of the program for `drive`.
    pub fn program_for(&self, drive: &Drive) -> Option<usize> {
        let mode = match drive {
            Drive::Velocity => "velocity",
            Drive::Force(_) => "force",
        };
        self.lowered.programs.iter().position(|p| p.mode == mode)
    }

    /// A run's integrator for `params` under `drive`.
    pub fn stepper<'a>(&'a self, params: &[f64], drive: &'a Drive) -> Option<EventStepper<'a>> {
        let i = self.program_for(drive)?;
        let force = drive.force_table();
        Some(EventStepper::new(
            &self.lowered.programs[i],
            &self.tapes[i],
            params,
            force,
        ))
    }
}

impl CompiledRig {
    /// A lumped rig model: its parameters, its equations and how to pack them for the
    /// GPU.
    /// The rig's id (its file's `"id"`).
    pub fn id(&self) -> &str {
        &self.id
    }

    /// The model's parameters, in the order of every parameter vector.
    pub fn params(&self) -> &[ParamInfo] {
        &self.params
    }

    /// Names of the state variables.
    pub fn state_names(&self) -> &[String] {
        &self.states
    }

    /// Names and units of the outputs; output 0 is fitted to the measurement.
    pub fn output_names(&self) -> &[(String, String)] {
        &self.outputs
    }

    /// Whether the model can run under `drive` (a rig without a force-mode
    /// drive cannot take a force table).
    pub fn supports(&self, drive: &Drive) -> bool {
        self.program_for(drive).is_some()
    }

    /// Checks a full parameter vector for physical sense (positive masses, …).
    /// Returns the offending parameter's name and what was expected.
    pub fn check(&self, params: &[f64]) -> Result<(), (&str, String)> {
        for (i, info) in self.params.iter().enumerate() {
            if !params[i].is_finite() {
                return Err((&info.name, "a finite number".into()));
            }
        }
        for node in &self.desc.nodes {
            if let Coef::Param(n) = &node.mass {
                let i = self.param_index(n);
                if params[i] <= 0.0 {
                    return Err((&self.params[i].name, "a mass > 0".into()));
                }
            }
        }
        for e in &self.desc.elements {
            if let (Some(_), Some(DamperLaw::Viscous { c: Coef::Param(n) })) =
                (&e.backlash, &e.damper)
            {
                let i = self.param_index(n);
                if params[i] <= 0.0 {
                    return Err((
                        &self.params[i].name,
                        format!(
                            "a damping > 0 (backlash element {:?}: its play moves with ṗ = ė + F_s/c)",
                            e.name
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Integrates one run from rest with the f64 RK4 reference, calling `observe`
    /// at every sample of `grid`.
    pub fn simulate(
        &self,
        params: &[f64],
        drive: &Drive,
        grid: &SampleGrid,
        observe: &mut dyn FnMut(&Sample<'_>) -> ControlFlow<()>,
    ) {
        let n_out = self.outputs.len();
        let n = self.states.len();
        let Some(mut st) = self.stepper(params, drive) else {
            // A drive mode the rig does not declare (refused by campaign
            // validation): every output is NaN, so the run counts as diverged.
            let nan = vec![f64::NAN; n_out.max(n)];
            for k in 0..grid.samples {
                let s = Sample {
                    index: k,
                    t: grid.time(k),
                    state: &nan[..n],
                    outputs: &nan[..n_out],
                };
                if observe(&s).is_break() {
                    return;
                }
            }
            return;
        };
        let mut y = st.y0.clone();
        let mut outs = vec![0.0; n_out];
        let mut full = vec![0.0; n];
        let mut ctx = (&mut st, &mut y);
        walk_grid(
            grid,
            &mut ctx,
            |(st, y), t, h| st.step(t, h, y),
            |(st, y), k, t| {
                st.report(t, y, &mut outs, &mut full);
                if st.chattered {
                    outs.fill(f64::NAN);
                }
                observe(&Sample {
                    index: k,
                    t,
                    state: &full,
                    outputs: &outs,
                })
            },
        );
    }

    /// Runs several parameter vectors on one grid, calling `observe(run,
    /// sample)` at every sample of each until its observer breaks, with what
    /// `report` asks for in each sample. By default one run after the other;
    /// a model with a lane-batched ensemble (see [`crate::model::CompiledRig::lanes`]) advances
    /// them together, with the same results.
    pub fn simulate_many(
        &self,
        params: &[&[f64]],
        drive: &Drive,
        grid: &SampleGrid,
        report: Report,
        observe: &mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ) {
        let Some(i) = self.program_for(drive) else {
            super::many_one_by_one(self, params, drive, grid, report, observe);
            return;
        };
        let native = Self::native_for(&self.native[i], &self.lane_code[i], params, grid);
        self.run_lanes(
            self.lane_parts(i),
            drive,
            params,
            grid,
            native.as_deref(),
            Observe::Each(report, observe),
        );
    }

    /// Output 0 alone of several runs on one grid, each sample's values for a
    /// group of runs handed to `observe` at once (what the fitness needs,
    /// without a call per run and sample). `live` has a bit per run of the
    /// group (bit `j`: run `first + j`) still observed: the observer clears a
    /// run's bit to stop observing it, and the group ends when none is left.
    /// With `f32`, in f32 arithmetic where the model has an f32 path here (a
    /// compiled rig whose lane code the C compiler built), held to the f32
    /// tolerance of the f64 reference as the GPU's f32 kernels are. Returns
    /// whether it ran in f32. By default one run after the other, in f64.
    pub fn simulate_measured(
        &self,
        params: &[&[f64]],
        drive: &Drive,
        grid: &SampleGrid,
        f32: bool,
        observe: &mut dyn FnMut(&MeasuredSample<'_>, &mut u64),
    ) -> bool {
        let Some(i) = self.program_for(drive) else {
            super::measured_one_by_one(self, params, drive, grid, observe);
            return false;
        };
        // Output 0 only: the fitness variant where it skips switches.
        let (parts, slots) = match &self.fitness[i] {
            Some(f) => (
                (&f.program, &self.tapes[i], &f.lane_code),
                (&f.native, &f.native_f32),
            ),
            None => (self.lane_parts(i), (&self.native[i], &self.native_f32[i])),
        };
        let in_f32 = f32.then(|| slots.1.now(parts.2, Arith::F32)).flatten();
        let native = in_f32
            .clone()
            .or_else(|| Self::native_for(slots.0, parts.2, params, grid));
        self.run_lanes(
            parts,
            drive,
            params,
            grid,
            native.as_deref(),
            Observe::Measured(observe),
        );
        in_f32.is_some()
    }

    /// How many runs [`crate::model::CompiledRig::simulate_many`] advances together (1: no
    /// gain from grouping runs).
    pub fn lanes(&self) -> usize {
        LANES
    }

    /// How the model runs in the GPU ensemble kernels under `drive` (every
    /// experiment of a GPU batch must get the same kernels); `None` keeps it
    /// CPU-only.
    pub fn gpu(&self, drive: &Drive) -> Option<super::GpuModel> {
        let i = self.program_for(drive)?;
        self.gpu[i].clone()
    }

    /// What [`crate::model::CompiledRig::linearise`] linearises about, in words, for the header
    /// of `rigfit modes`.
    pub fn linearisation_point(&self) -> String {
        self.rest_point()
    }

    /// The rig linearised about its engaged, unbroken configuration.
    pub fn linearise(&self, params: &[f64], drive: &Drive) -> Linearised {
        self.linearise_at_rest(params, drive)
    }

    /// Upper bound on the highest natural frequency (rad/s) of any parameter
    /// vector inside `[lower, upper]`, with the name of the parameter that limits
    /// it most. Used to choose or refuse the RK4 step.
    pub fn omega_bound(&self, lower: &[f64], upper: &[f64], drive: &Drive) -> (f64, String) {
        self.omega_bound_in_run(lower, upper, drive, f64::INFINITY)
    }

    /// [`Self::omega_bound`] for a run of model time `0..t_end` (s): a model
    /// whose stiffness grows with a displacement may bound that displacement by
    /// what the drive reaches in that time. The default ignores `t_end`.
    pub fn omega_bound_in_run(
        &self,
        lower: &[f64],
        upper: &[f64],
        drive: &Drive,
        t_end: f64,
    ) -> (f64, String) {
        // The graph's interval bound where it is finite and no looser than the
        // per-law one; the per-law one otherwise (see `interval_omega`).
        let old = self.per_law_omega(lower, upper, drive);
        match self.interval_omega(lower, upper, drive, t_end) {
            Some(new) if new.0.is_finite() && new.0 <= old.0 => new,
            _ => old,
        }
    }
}
