//! One small module per subcommand. Each has the same entry, `run(&Global, &Options) -> exit status`, and
//! takes plain settings: the command line (`cli.rs`) parses and checks the arguments and calls it.

pub mod clear_errors;
pub mod commission;
pub mod completions;
pub mod config;
pub mod dashboard;
pub mod decode;
pub mod doctor;
pub mod drive;
pub mod lights;
pub mod live;
pub mod mode;
pub mod monitor;
pub mod record;
pub mod report;
pub mod same_file;
pub mod send_raw;
pub mod sim;

use crate::link::LinkChoice;
use crate::output::ColorChoice;
use crate::protocol::ProtocolHint;

/// The settings every command gets (the global options).
#[derive(Clone, Debug)]
pub struct Global {
    /// The link to the robot; `decode` and `completions` never open it.
    pub link: LinkChoice,
    pub color: ColorChoice,
    pub protocol: ProtocolHint,
    /// Faults the `--sim` robot is given (`--fault NAME@TIME`); the command line allows them only with `--sim`.
    pub sim_faults: Vec<crate::sim::ScheduledFault>,
    /// Chassis parameters of the `--sim` robot (`--sim-param NAME=VALUE`, checked); only with `--sim`.
    pub sim_params: Vec<crate::sim::SimParamSetting>,
    /// The low-battery threshold, volts: `battery.warning_volts` of the configuration files, else the
    /// manual's alarm voltage (`protocol::constants::BATTERY_WARNING_DV`).
    pub battery_warning_volts: f64,
}

impl Global {
    /// The in-process robot's settings for `--sim` (its faults and parameters); `None` for other links.
    pub fn sim_config(&self) -> Option<crate::sim::SimConfig> {
        matches!(self.link, LinkChoice::Sim).then(|| {
            let mut config = crate::sim::SimConfig { faults: self.sim_faults.clone(), ..Default::default() };
            self.sim_params.iter().for_each(|param| param.apply(&mut config));
            config
        })
    }
}

/// A usage error (exit status 2) with this message.
pub fn usage(message: impl Into<String>) -> anyhow::Error {
    crate::exit::Failure { code: crate::exit::USAGE, message: message.into() }.into()
}
