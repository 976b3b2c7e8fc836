//! The `entrynav-dev` binary (the tools are in the `entrynav_devtools` library, whose command
//! tree `tests/option_walk.rs` walks).

fn main() {
    entrynav_devtools::main_entry();
}
