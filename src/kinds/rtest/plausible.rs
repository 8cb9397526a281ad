//! What an R-test table's own data say against its labels, as a caution for the report and
//! a problem `identify` refuses to compensate from: a test that repeats another reading for
//! reading ([`crate::io::plausible::copied_block`]: a test exported twice, or pasted under a
//! new name). (Whether an angle column is the tilting axis's or the turntable's only the
//! machine can say: `identify` checks every angle against its joint's limits.)

use super::table::RtestTable;
use crate::io::plausible::{Block, copied_block, copy_sentence};

/// The deviations of each test as blocks (x, y, z of every row, in file order).
pub fn test_blocks(table: &RtestTable) -> Vec<Block> {
    let mut blocks: Vec<Block> = Vec::new();
    for row in &table.rows {
        let label = format!("test \"{}\"", row.test);
        let index = match blocks.iter().position(|b| b.label == label) {
            Some(index) => index,
            None => {
                blocks.push(Block {
                    label,
                    readings: Vec::new(),
                });
                blocks.len() - 1
            }
        };
        blocks[index]
            .readings
            .extend([row.deviation.x, row.deviation.y, row.deviation.z]);
    }
    blocks
}

/// A test that repeats another reading for reading.
pub fn copied_test(table: &RtestTable) -> Option<String> {
    let blocks = test_blocks(table);
    copied_block(&blocks).map(|pair| copy_sentence(&blocks, pair))
}
