//! The `entrynav` binary (the commands are in the `entrynav_cli` library).

/// mimalloc instead of the system allocator: a Monte Carlo run makes hundreds of thousands of
/// small short-lived allocations (per-epoch measurement lists, fusion work space), which glibc's
/// malloc served at about 6 % of a four-beacon-fusion trade's instructions (docs/results.md,
/// *Monte Carlo speed*). It changes no result (allocation does not touch the arithmetic).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    entrynav_cli::cli_main();
}
