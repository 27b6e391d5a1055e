//! The `vkpath` command line. Errors are printed as one line and exit with status 1; usage
//! errors exit with status 2 (clap's convention).

use clap::Parser;

fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format(log_line)
        .init();
    let cli = vkpath::cli::Cli::parse();
    if let Err(error) = vkpath::cli::run(cli) {
        eprintln!("vkpath: error: {error:#}");
        // A usage error found after parsing exits as clap's do.
        let usage = error.is::<vkpath::cli::frames::UsageError>();
        std::process::exit(if usage { 2 } else { 1 });
    }
}

/// How a log record reaches the terminal: a warning or an error as the command's own lines
/// are written ("vkpath: warning: ..."), not as "[WARN vkpath::render::renderer] ..."; the
/// levels only `RUST_LOG` shows keep their level and module, for whoever asked for them.
fn log_line(out: &mut env_logger::fmt::Formatter, record: &log::Record) -> std::io::Result<()> {
    use std::io::Write;
    match record.level() {
        log::Level::Error => writeln!(out, "vkpath: error: {}", record.args()),
        log::Level::Warn => writeln!(out, "vkpath: warning: {}", record.args()),
        level => writeln!(out, "[{level} {}] {}", record.target(), record.args()),
    }
}
