//! The `entrynav` binary (the commands are in the `entrynav_cli` library).

/// mimalloc instead of the system allocator: each filter's run makes tens of thousands of small
/// short-lived allocations (per-epoch measurement lists, fusion work space; callgrind counted
/// about 31 000 per `ci` run of four-beacon-fusion), which glibc's malloc served at about 6 % of a
/// fusion trade's instructions (docs/results.md, *Monte Carlo speed*). It changes no result
/// (allocation does not touch the arithmetic).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    entrynav_cli::cli_main();
}
