//! The `isotrace` command line; it lives in the library (`isotrace::command_line`).

fn main() -> std::process::ExitCode {
    isotrace::command_line()
}
