//! Entry guidance studies (`entrynav guidance`): the delivery Monte Carlo with filters in the
//! loop ([`deliver`], also what a trade of a scenario with `[guidance]` adds) and the reference
//! trajectory with its gains ([`reference`](mod@reference)), and what a delivery table must warn
//! about ([`delivery_warnings`]).

pub mod deliver;
pub mod delivery_warnings;
pub mod reference;

pub use deliver::{DeliverOptions, DeliveryStudy, delivery_of_study, run_deliver};
pub use reference::{GuidanceReference, run_reference};
