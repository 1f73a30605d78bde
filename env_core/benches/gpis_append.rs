//! Criterion benchmark of the GPIS contact append against a full recompute (being written).

fn main() {}
