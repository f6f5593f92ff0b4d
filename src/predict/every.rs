//! Every pixel on its own: one pass, no voters. The order of `brute` (each pixel traces every
//! light) and `none` (each pixel sees every light).

use super::order::Order;

/// One pass over the tile, no pixel reading another.
pub struct EveryPixel;

impl Order for EveryPixel {
    fn name(&self) -> &'static str {
        "every-pixel"
    }
}
