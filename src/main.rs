//! The `vkpath` command line. Errors are printed as one line and exit with status 1; usage
//! errors exit with status 2 (clap's convention).

use clap::Parser;

fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format(|out, record| {
            use std::io::Write;
            writeln!(out, "{}", vkpath::cli::log_line(record))
        })
        .init();
    let cli = vkpath::cli::Cli::parse();
    if let Err(error) = vkpath::cli::run(cli) {
        eprintln!("vkpath: error: {error:#}");
        // A usage error found after parsing exits as clap's do.
        let usage = error.is::<vkpath::cli::frames::UsageError>();
        std::process::exit(if usage { 2 } else { 1 });
    }
}
