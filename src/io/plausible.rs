//! What a table's data can say about themselves, beyond each value's range: a block of
//! readings (a run, a test, a sense, a feature) that is a copy of another, and a spread of
//! readings too small or too large for the instrument and the machine. The kinds turn these
//! into refusals (`identify`, whose outputs drive a machine) or into cautions (`analyze`).
//!
//! A copy is judged by bit-identical readings: an instrument's noise and a machine's drift
//! make two real blocks of [`MIN_COPY_READINGS`] or more readings differ somewhere, so
//! identical blocks are the same readings counted twice (a run pasted under a new label, a
//! test exported twice), and each would shrink every uncertainty by √2. Only a noise-free
//! simulation repeats itself exactly, and the messages say so.

use crate::math::Real;

/// The fewest readings two blocks must share for their being identical to count as a copy:
/// with a noise of even one resolution step, three equal readings in a row happen by chance
/// with a probability of order (1/ number of steps in the noise)³.
pub const MIN_COPY_READINGS: usize = 3;

/// A block of readings: its label (as the file names it) and its readings in file order, in
/// whatever unit the kind reads them (compared bit for bit, so only equal text gives equal
/// readings).
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// The block's name in the file (`run "3"`, `test "CK1 A0"`, `the ccw sense`).
    pub label: String,
    /// The readings that would be counted, in file order.
    pub readings: Vec<Real>,
}

/// The first two blocks (by index, the earlier first) that hold the same readings in the same
/// order, with at least [`MIN_COPY_READINGS`] of them and not all equal to one value (a
/// constant block, such as zeros at a reference, is not evidence of a copy).
pub fn copied_block(blocks: &[Block]) -> Option<(usize, usize)> {
    for (j, later) in blocks.iter().enumerate() {
        let r = &later.readings;
        if r.len() < MIN_COPY_READINGS || r.iter().all(|v| v.to_bits() == r[0].to_bits()) {
            continue;
        }
        if let Some(i) = blocks[..j].iter().position(|earlier| {
            earlier.readings.len() == r.len()
                && earlier
                    .readings
                    .iter()
                    .zip(r)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
        }) {
            return Some((i, j));
        }
    }
    None
}

/// The sentence for a copy [`copied_block`] found (the caller names the file).
pub fn copy_sentence(blocks: &[Block], (i, j): (usize, usize)) -> String {
    format!(
        "{} holds the same {} readings as {}, reading for reading: a copy would count them twice (every uncertainty √2 too small); no instrument repeats its noise, only a noise-free simulation does",
        blocks[j].label,
        blocks[j].readings.len(),
        blocks[i].label
    )
}

/// The range of air temperatures a machine shop has (°C): 0 … 40 °C, from an unheated hall
/// in winter to a hot one in summer. Air read outside it is in another unit (°F: 20 °C reads
/// 68; kelvin are refused by the thermometer's range).
pub const SHOP_AIR_DEGC: (Real, Real) = (0.0, 40.0);

/// The caution for an air temperature column `column` whose median lies outside
/// [`SHOP_AIR_DEGC`].
pub fn air_caution(column: &str, values: &[Real]) -> Option<String> {
    let middle = median(values.to_vec())?;
    let (lo, hi) = SHOP_AIR_DEGC;
    (!(lo..=hi).contains(&middle)).then(|| {
        format!(
            "column `{column}`: the air reads {} °C (median), outside the {lo} … {hi} °C of any machine shop: °F in the °C column?",
            crate::math::trimmed(middle, 2)
        )
    })
}

/// Max − min of `values` (0 for none).
pub fn spread(values: impl IntoIterator<Item = Real>) -> Real {
    let (lo, hi) = values
        .into_iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if hi >= lo { hi - lo } else { 0.0 }
}

/// The median of `values` (None for none).
pub fn median(mut values: Vec<Real>) -> Option<Real> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(Real::total_cmp);
    let n = values.len();
    Some(if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(label: &str, readings: &[Real]) -> Block {
        Block {
            label: label.into(),
            readings: readings.to_vec(),
        }
    }

    #[test]
    fn a_pasted_block_is_found_and_a_noisy_repeat_is_not() {
        let blocks = [
            block("run 1", &[0.1, 0.2, 0.3]),
            block("run 2", &[0.1, 0.2, 0.300_001]),
            block("run 3", &[0.1, 0.2, 0.3]),
        ];
        assert_eq!(copied_block(&blocks), Some((0, 2)));
        assert_eq!(copied_block(&blocks[..2]), None);
        let sentence = copy_sentence(&blocks, (0, 2));
        assert!(sentence.starts_with("run 3 holds the same 3 readings as run 1"));
    }

    #[test]
    fn short_or_constant_blocks_are_not_copies() {
        let short = [block("a", &[1.0, 2.0]), block("b", &[1.0, 2.0])];
        assert_eq!(copied_block(&short), None);
        let zeros = [block("a", &[0.0; 5]), block("b", &[0.0; 5])];
        assert_eq!(copied_block(&zeros), None);
    }

    #[test]
    fn spread_and_median_by_hand() {
        assert_eq!(spread([3.0, -1.0, 2.0]), 4.0);
        assert_eq!(spread(std::iter::empty()), 0.0);
        assert_eq!(median(vec![5.0, 1.0, 3.0]), Some(3.0));
        assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(vec![]), None);
    }
}
