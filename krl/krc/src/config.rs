//! How to run the KRC-like runtime.

use std::path::PathBuf;
use std::time::Duration;

use kuka_kinematics::{Axes, PlanSettings, RobotModel};

/// Settings of a [`KrcController`](crate::KrcController).
#[derive(Debug, Clone)]
pub struct KrcConfig {
    /// The channel folder: the KRL file functions' root (on a KRC,
    /// `C:\KRC\ROBOTER\UserFiles`), where `kb_cmd.txt`, `kb_res.txt` and
    /// `kb_state.txt` live.
    pub channel_dir: PathBuf,
    /// Where `RUN` finds uploaded modules (`kbu<n>.src`/`.dat`); default
    /// `<channel_dir>/programs`, where the service puts them.
    pub program_dir: PathBuf,
    /// The KRL program to run instead of the shipped one: a folder with
    /// `kb_main.src`, `kb_main.dat`, `kb_submit.src`, `kb_io.src`,
    /// `kb_io.dat` and `kb_sps_lines.src` (a site's modified copy).
    pub krl_dir: Option<PathBuf>,
    /// Robot model.
    pub model: RobotModel,
    /// Axis angles at start (default: the model's home).
    pub start_axes: Option<Axes>,
    /// Simulated time per interpreter cycle (a KRC: 12 ms).
    pub cycle: Duration,
    /// Statements the Submit interpreter may run per cycle; a pass of its
    /// loop continues in the next cycle when the slice is used up, and a
    /// pass that needs more than one whole slice counts as an overrun. KUKA publishes no figure: an assumption, to be changed
    /// when measured on a controller.
    pub submit_budget: u64,
    /// Most passes of the Submit loop begun in one cycle (0 = no limit).
    /// A real Submit loop may run a short pass several times per cycle;
    /// they would see the same `$ROB_TIMER` and do nothing new, so the
    /// runtime runs one (default) and spends no time on the rest. It
    /// changes how often an idle loop looks at the command file (once a
    /// cycle), not what a pass costs.
    pub submit_passes_per_cycle: u32,
    /// Statements the robot interpreter may run per cycle.
    pub robot_budget: u64,
    /// Simulated seconds per wall-clock second: 1.0 = real time, 0 = as
    /// fast as possible (the clock still counts every cycle).
    pub time_scale: f64,
    /// Planner settings.
    pub plan: PlanSettings,
    /// Operating mode: `T1`, `T2`, `AUT` or `EX` (`$MODE_OP`).
    pub mode: String,
    /// `RET1` the simulated KSS answers for a file function that
    /// succeeded: `DATA_OK` (KUKA's text, working code) or `CMD_OK` (the
    /// other variant public CWRITE documentation allows).
    pub fct_success: String,
    /// What `SREAD`/`SWRITE`'s offset counts: 0 = characters already read
    /// or written (default), 1 = the 1-based position of the next one (the
    /// other reading of KUKA's text; the shipped program then parses and
    /// formats by characters, docs/CONTROLLER.md B20).
    pub text_offset_base: i64,
    /// The path prefix `RUN` accepts (`RUN /R1/kbu3()`): `/R1/` as every
    /// public `sps.sub` writes it; a KSS that wants the folder would take
    /// `/R1/Program/kbridge/`.
    pub run_prefix: String,
    /// `kb_run_pfx` as a site set it in `kb_main.dat` to match its KSS
    /// (`None`: as the program's `.dat` file says, `/R1/`). Set together
    /// with [`run_prefix`](Self::run_prefix) to run the program against
    /// the other RUN path variant (docs/CONTROLLER.md A2).
    pub site_run_prefix: Option<String>,
    /// Start `kb_main` at boot, as the operator or PLC does (in EXT mode
    /// the program can also start it itself with `kb_ext_autorun`).
    pub start_main: bool,
    /// Most trace samples kept (one per cycle; oldest dropped).
    pub trace_capacity: usize,
}

impl KrcConfig {
    /// Defaults for a channel folder: KR 3 R540, 12 ms cycles, real time,
    /// EXT mode, `kb_main` started.
    pub fn new(channel_dir: impl Into<PathBuf>) -> Self {
        let channel_dir: PathBuf = channel_dir.into();
        KrcConfig {
            program_dir: channel_dir.join("programs"),
            channel_dir,
            krl_dir: None,
            model: RobotModel::kr3_r540(),
            start_axes: None,
            cycle: Duration::from_millis(12),
            submit_budget: 500,
            submit_passes_per_cycle: 1,
            robot_budget: 5_000,
            time_scale: 1.0,
            plan: PlanSettings::default(),
            mode: "EX".into(),
            fct_success: "DATA_OK".into(),
            text_offset_base: 0,
            run_prefix: "/R1/".into(),
            site_run_prefix: None,
            start_main: true,
            trace_capacity: 100_000,
        }
    }
}
