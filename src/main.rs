use clap::Parser;

fn main() {
    let _cli = relief::cli::Cli::parse();
}
