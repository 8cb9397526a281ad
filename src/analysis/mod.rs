//! Analyses: the standards' figures from measurement tables, simulated or real alike.

pub mod iso230_2;
pub mod iso230_3;
pub mod iso230_4;
pub mod thermal_series;
