//! [`PerTraining`]: what a search computes once per training set (a fold's readings) and asks
//! for many times, every model and every pass; [`PerValue`]: what it computes for a searched
//! value (a time constant) that every fold and model asks for again (the grid's points).

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Values made once per key (searched values, as their bits), when first asked for, keeping at
/// most [`PerValue::CAPACITY`]: the search grid's points come first and are asked for again by
/// every fold and model; a refinement's points rarely recur, and past the capacity a value is
/// made and not kept. A clone starts empty: what it holds is a pure function of the problem
/// and the key, so what is kept changes no result.
pub(super) struct PerValue<T>(Mutex<HashMap<[Option<u64>; 2], Arc<T>>>);

impl<T> PerValue<T> {
    /// At most this many values are kept (each one value per reading: 256 × 8 B per reading).
    pub(super) const CAPACITY: usize = 256;

    /// The value for `key`, made by `make` if not yet held.
    pub(super) fn get(&self, key: [Option<f64>; 2], make: impl FnOnce() -> T) -> Arc<T> {
        let key = key.map(|v| v.map(f64::to_bits));
        if let Some(v) = self.0.lock().expect("not poisoned").get(&key) {
            return Arc::clone(v);
        }
        let made = Arc::new(make());
        let mut values = self.0.lock().expect("not poisoned");
        if let Some(v) = values.get(&key) {
            return Arc::clone(v);
        }
        if values.len() < Self::CAPACITY {
            values.insert(key, Arc::clone(&made));
        }
        made
    }
}

impl<T> Default for PerValue<T> {
    fn default() -> PerValue<T> {
        PerValue(Mutex::new(HashMap::new()))
    }
}

impl<T> Clone for PerValue<T> {
    fn clone(&self) -> PerValue<T> {
        PerValue::default()
    }
}

impl<T> std::fmt::Debug for PerValue<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let held = self.0.lock().map_or(0, |v| v.len());
        write!(f, "PerValue({held} held)")
    }
}

/// Values made once per training set (a mask over the readings), when first asked for. A
/// clone starts empty: what it holds is a pure function of the problem and the mask.
pub(super) struct PerTraining<T>(Mutex<Vec<(Vec<bool>, Arc<T>)>>);

impl<T> PerTraining<T> {
    /// The value for the training set `train`, made by `make` if not yet held. Two threads
    /// asking at once may both make it; they make the same thing, and the first kept is used.
    pub(super) fn get(&self, train: &[bool], make: impl FnOnce() -> T) -> Arc<T> {
        let held = |values: &[(Vec<bool>, Arc<T>)]| {
            values
                .iter()
                .find(|(mask, _)| mask == train)
                .map(|(_, v)| Arc::clone(v))
        };
        if let Some(v) = held(&self.0.lock().expect("not poisoned")) {
            return v;
        }
        let made = Arc::new(make());
        let mut values = self.0.lock().expect("not poisoned");
        if let Some(v) = held(&values) {
            return v;
        }
        values.push((train.to_vec(), Arc::clone(&made)));
        made
    }
}

impl<T> PerTraining<(Vec<f64>, T)> {
    /// The value for `train` made for `knots` (a fit's reference knots, which the training set
    /// decides): kept per training set; one asked for with other knots is made afresh and not
    /// kept.
    pub(super) fn get_for_knots(
        &self,
        train: &[bool],
        knots: &[f64],
        make: impl Fn() -> T,
    ) -> Arc<(Vec<f64>, T)> {
        let held = self.get(train, || (knots.to_vec(), make()));
        if held.0 == knots {
            held
        } else {
            Arc::new((knots.to_vec(), make()))
        }
    }
}

impl<T> Default for PerTraining<T> {
    fn default() -> PerTraining<T> {
        PerTraining(Mutex::new(Vec::new()))
    }
}

impl<T> Clone for PerTraining<T> {
    fn clone(&self) -> PerTraining<T> {
        PerTraining::default()
    }
}

impl<T> std::fmt::Debug for PerTraining<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let held = self.0.lock().map_or(0, |v| v.len());
        write!(f, "PerTraining({held} held)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_value_is_made_once_per_mask_and_a_clone_starts_empty() {
        let memo: PerTraining<usize> = PerTraining::default();
        let made = AtomicUsize::new(0);
        let make = |v: usize| {
            made.fetch_add(1, Ordering::Relaxed);
            v
        };
        assert_eq!(*memo.get(&[true, false], || make(1)), 1);
        assert_eq!(*memo.get(&[true, false], || make(2)), 1);
        assert_eq!(*memo.get(&[false, true], || make(3)), 3);
        assert_eq!(made.load(Ordering::Relaxed), 2);
        assert_eq!(*memo.clone().get(&[true, false], || make(4)), 4);
    }
}
