//! The `entrynav` binary (the commands are in the `entrynav_cli` library).

fn main() {
    entrynav_cli::cli_main();
}
