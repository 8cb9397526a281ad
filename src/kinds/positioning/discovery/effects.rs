//! The effect library: each effect positioning discovery can add to the base model, with its
//! stable identifier, its physical cause and the shape of its terms.

/// The effects positioning discovery can add to the base model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PositioningEffect {
    /// Constant lost motion `v`: the reading is `−s·v/2`.
    Reversal,
    /// Lost motion changing along the axis: `−s·k·(x − x_c)/2` about the targets' centre.
    ReversalPosition,
    /// Lost motion changing with temperature: `−s·k·(T − T_ref)/2`.
    ReversalThermal,
    /// The expanding structure follows a first-order lag (τ) of the measured temperature.
    ThermalLag,
    /// The sensor follows a first-order lag (τ) of the structure's temperature: the
    /// structure's is the measured one plus `τ·dT/dt`.
    SensorLag,
    /// Expansion coefficient different from the nominal one: `Δα·x·(T − T_ref)`.
    ThermalScale,
    /// Origin drift with temperature: `c·(T − T_ref)`.
    ThermalOffset,
    /// Expansion driven by machine activity since the first reading: `b·x·(1 − e^(−t/τ))`.
    SecondHeatSource,
    /// Cyclic error `a·sin(2πx/p) + b·cos(2πx/p)`, period `p` searched.
    Periodic,
    /// Quadratic and cubic terms in position beyond the profile's knots.
    NonlinearScale,
    /// Drift linear in time not explained by temperature: `d·(t − t_ref)`.
    TimeDrift,
}

impl PositioningEffect {
    /// Every effect, in the order they are reported.
    pub const ALL: [PositioningEffect; 11] = [
        PositioningEffect::Reversal,
        PositioningEffect::ReversalPosition,
        PositioningEffect::ReversalThermal,
        PositioningEffect::ThermalLag,
        PositioningEffect::SensorLag,
        PositioningEffect::ThermalScale,
        PositioningEffect::ThermalOffset,
        PositioningEffect::SecondHeatSource,
        PositioningEffect::Periodic,
        PositioningEffect::NonlinearScale,
        PositioningEffect::TimeDrift,
    ];

    /// The stable identifier.
    pub fn id(self) -> &'static str {
        match self {
            PositioningEffect::Reversal => "reversal",
            PositioningEffect::ReversalPosition => "reversal_position",
            PositioningEffect::ReversalThermal => "reversal_thermal",
            PositioningEffect::ThermalLag => "thermal_lag",
            PositioningEffect::SensorLag => "sensor_lag",
            PositioningEffect::ThermalScale => "thermal_scale",
            PositioningEffect::ThermalOffset => "thermal_offset",
            PositioningEffect::SecondHeatSource => "second_heat_source",
            PositioningEffect::Periodic => "periodic",
            PositioningEffect::NonlinearScale => "nonlinear_scale",
            PositioningEffect::TimeDrift => "time_drift",
        }
    }

    /// The physical cause, as a metrologist would name it.
    pub fn cause(self) -> &'static str {
        match self {
            PositioningEffect::Reversal => {
                "lost motion (backlash): play and elastic wind-up in the screw, nut and drive leave the axis short of the target in the direction of travel"
            }
            PositioningEffect::ReversalPosition => {
                "lost motion that changes along the travel: uneven nut preload or screw wear, guideway friction varying with position"
            }
            PositioningEffect::ReversalThermal => {
                "lost motion that changes with temperature: nut preload and friction changing as the drive warms"
            }
            PositioningEffect::ThermalLag => {
                "the expanding structure (the screw) warms later than the sensor reads: its effective temperature is a first-order lag of the measured one"
            }
            PositioningEffect::SensorLag => {
                "the sensor warms later than the structure it stands for (in a housing, glued on through a thick layer, on a slower part): the structure's temperature is the reading plus the sensor's time constant times the reading's rate of change"
            }
            PositioningEffect::ThermalScale => {
                "the axis expands per degree differently from the nominal coefficient: another material, a sensor that is not at the screw's temperature, or thermal compensation in the control"
            }
            PositioningEffect::ThermalOffset => {
                "the axis origin moves with temperature: the screw's fixed end (thrust bearing) or the measurement zero is away from the axis zero, or the structure carrying the reference grows"
            }
            PositioningEffect::SecondHeatSource => {
                "a heat source the sensor does not see (motor, support bearings, the nut on the screw) expands the axis as the machine runs, with its own time constant"
            }
            PositioningEffect::Periodic => {
                "cyclic error with the period of the drive or scale: screw lead (pitch) error, thread drunkenness, scale interpolation error"
            }
            PositioningEffect::NonlinearScale => {
                "curved positioning error between the reference targets: lead error varying along the screw, guideway bending"
            }
            PositioningEffect::TimeDrift => {
                "slow drift with time that the temperature does not explain: laser set-up drift, creep, an unmeasured part of the environment"
            }
        }
    }

    /// Whether `a` and `b` are `thermal_lag` and `sensor_lag` (in either order), which no model
    /// holds together (see [`crate::discovery::engine::Problem::compatible`]).
    pub(super) fn lags(a: PositioningEffect, b: PositioningEffect) -> bool {
        matches!(
            (a, b),
            (PositioningEffect::ThermalLag, PositioningEffect::SensorLag)
                | (PositioningEffect::SensorLag, PositioningEffect::ThermalLag)
        )
    }

    /// Whether the effect has a searched (nonlinear) parameter.
    pub(super) fn searched(self) -> bool {
        matches!(
            self,
            PositioningEffect::ThermalLag
                | PositioningEffect::SensorLag
                | PositioningEffect::SecondHeatSource
                | PositioningEffect::Periodic
        )
    }

    /// Whether its columns are built on the temperature rise (and so change with a lag's
    /// time constant).
    pub(super) fn uses_rise(self) -> bool {
        matches!(
            self,
            PositioningEffect::ReversalThermal
                | PositioningEffect::ThermalScale
                | PositioningEffect::ThermalOffset
        )
    }

    /// The number of linear coefficients it adds.
    pub(super) fn columns(self) -> usize {
        match self {
            PositioningEffect::ThermalLag | PositioningEffect::SensorLag => 0,
            PositioningEffect::Periodic | PositioningEffect::NonlinearScale => 2,
            _ => 1,
        }
    }
}
