//! The `holoc` command: parses arguments and hands over to [`holoc::cli::run`].

use clap::Parser as _;

fn main() -> std::process::ExitCode {
    // A panic inside the diagnostic renderer is caught and the diagnostic printed plainly;
    // the default hook would still print the panic's message, so it is kept quiet then.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !holoc::diag::format::is_drawing() {
            default_hook(info);
        }
    }));
    holoc::cli::run(holoc::cli::Cli::parse())
}
