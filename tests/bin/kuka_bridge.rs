//! The kuka-bridge command line, built inside the test crate so tests can
//! run it as a separate process (a simulated controller to kill or hang).

fn main() -> std::process::ExitCode {
    kuka_bridge::cli::main()
}
