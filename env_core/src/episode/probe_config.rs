//! The settings of the `probe` action mode (`probe_*`, a section of
//! [`super::config::EpisodeConfig`]): how many lanes, depths and sweeps an action chooses
//! from, and how the controller of [`super::probe`] turns the finger.

use crate::scene::HandConfig;
use crate::settings;
use crate::settings::{Range, SettingError};

settings! {
    /// The probes of the `probe` action mode and how the controller carries them out.
    pub struct ProbeConfig {
        /// Lanes across the opening a probe can go in by (the first action index).
        lanes: usize = 29 => "probe_lanes" in Range::closed(1.0, 1000.0),
        /// Wrist depths a probe can go to (the second action index).
        depths: usize = 10 => "probe_depths" in Range::closed(1.0, 1000.0),
        /// Sweep angles a probe can turn the finger to (the third action index); odd counts
        /// include 0 (no turn).
        sweeps: usize = 9 => "probe_sweeps" in Range::closed(1.0, 1000.0),
        /// Largest sweep angle either way, rad.
        max_angle: f64 = 1.0 => "probe_max_angle" in Range::left_open(0.0, 1.5),
        /// The controller's turn per motion while sweeping, rad (at most the hand's
        /// max_step_yaw).
        sweep_rate: f64 = 0.05 => "probe_sweep_rate" in Range::left_open(0.0, 1.5),
    }
    sections {}
    check_across = |_| Ok(());
}

impl ProbeConfig {
    /// The action's index counts: `[lanes, depths, sweeps]`.
    pub fn counts(&self) -> [usize; 3] {
        [self.lanes, self.depths, self.sweeps]
    }
}

/// The sweep rate must not exceed the hand's turn per step.
pub fn check_sweep_rate(probe: &ProbeConfig, hand: &HandConfig) -> Result<(), SettingError> {
    if probe.sweep_rate <= hand.max_step_yaw {
        Ok(())
    } else {
        Err(SettingError::out_of_range(
            "probe_sweep_rate",
            format!("at most max_step_yaw ({})", hand.max_step_yaw),
            probe.sweep_rate.to_string(),
        ))
    }
}
