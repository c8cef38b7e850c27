//! The kuka-bridge binary: everything lives in the library; see `cli`.

fn main() -> std::process::ExitCode {
    kuka_bridge::cli::main()
}
