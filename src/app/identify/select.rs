//! `identify --discover`: model selection before the estimate
//! ([`crate::estimate::discover`]), on the tables read as for the fit, each R-test table with
//! a drift rate the library may take.

use super::{IdentifyError, Request, load_readings};
use crate::estimate::discover::{self, Discovery};
use crate::kinds::rtest::readings::Drift;
use crate::machine::Machine;

/// Runs model selection on `request`'s tables for `machine` from its `--params`. R-test tables
/// are read with a drift rate when they carry their rows' times and `--drift` asks for none
/// (the library then holds it); with `--drift` given, the drift asked for is the base's.
pub fn select(request: &Request, machine: &Machine) -> Result<Discovery, IdentifyError> {
    let rated = Request {
        drift: Drift::Rate,
        ..request.clone()
    };
    let (loaded, offer_drift) = match request.drift {
        Drift::None => match load_readings(&rated, machine) {
            Ok(loaded) => (loaded, true),
            // Tables without their rows' times: no drift in the library.
            Err(_) => (load_readings(request, machine)?, false),
        },
        _ => (load_readings(request, machine)?, false),
    };
    if !loaded.problems.is_empty() && !request.accept_implausible {
        return Err(IdentifyError::Contradicted(super::checks::Findings {
            problems: loaded.problems,
            cause: "likely cause: the tables' own data contradict counting them as given; model selection would only dress it in terms".into(),
        }));
    }
    discover::discover(machine, &request.params, &loaded.sets, offer_drift, |_| {})
        .map_err(|e| IdentifyError::Input(format!("--discover: {e}")))
}
