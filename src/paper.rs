//! The paper's published figures (Ben-Artzi, Ramamoorthi & Agrawala 2004), for the commands
//! that print ours beside them: Table 1's share of shadow rays each method traces.

use crate::predict::Method;

/// The paper's Table 1: % of N·L > 0 shadow rays traced per method, for shapes then bunny at
/// 50, 100, 200 and 400 lights; its rows in the paper's order ("true" = brute first).
pub const TABLE1: [(&str, [f64; 8]); 6] = [
    ("brute", [100.0; 8]),
    (
        "scan-warp-boundary",
        [40.5, 34.3, 26.3, 22.4, 52.4, 42.6, 33.6, 25.9],
    ),
    (
        "grid-warp-boundary",
        [22.0, 17.9, 15.1, 12.4, 21.5, 16.6, 13.5, 11.6],
    ),
    (
        "grid-nowarp-boundary",
        [21.7, 17.1, 13.8, 10.6, 21.2, 15.8, 12.0, 9.3],
    ),
    (
        "grid-warp-uncertainty",
        [10.4, 10.7, 11.0, 11.3, 9.1, 9.4, 10.2, 11.5],
    ),
    (
        "grid-nowarp-uncertainty",
        [9.4, 8.8, 8.3, 7.5, 8.1, 7.7, 7.2, 6.7],
    ),
];

/// The methods of the paper's Table 1, in its row order.
pub fn table1_methods() -> Vec<Method> {
    TABLE1
        .iter()
        .map(|(name, _)| name.parse().expect("Table 1 names registered methods"))
        .collect()
}

/// The paper's Table 1 figure (% of N·L > 0 shadow rays traced) for this method, scene
/// (`shapes` or `bunny`) and light count, where the paper gives one.
pub fn paper_percent(method: Method, scene: &str, lights: usize) -> Option<f64> {
    let col = match lights {
        50 => 0,
        100 => 1,
        200 => 2,
        400 => 3,
        _ => return None,
    };
    let row = TABLE1.iter().find(|(name, _)| *name == method.name())?.1;
    match scene {
        "shapes" => Some(row[col]),
        "bunny" => Some(row[4 + col]),
        _ => None,
    }
}
