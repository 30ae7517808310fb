//! A reader that stops early (`harness ... | head`) ends the harness as it ends any other
//! tool: by SIGPIPE, with nothing on stderr. SIGPIPE itself stays ignored (Rust's default)
//! while the harness runs: a supervised worker that dies before reading what the harness
//! writes to it must give the harness an error to report, not end it without a word. So
//! the signal is raised only when printing to stdout fails with a broken pipe (std's
//! `print!` panics then).
/// Installs the panic hook that turns std's "failed printing to stdout: Broken pipe" into
/// death by SIGPIPE; every other panic goes to the hook that was there.
pub fn end_quietly_when_stdout_closes() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to stdout") && is_broken_pipe(message) {
            raise_sigpipe();
        }
        previous(info);
    }));
}

fn is_broken_pipe(message: &str) -> bool {
    // std formats the OS error: "Broken pipe (os error 32)" on Linux and the BSDs.
    message.contains("Broken pipe")
}

#[cfg(unix)]
fn raise_sigpipe() {
    // SAFETY: restoring the default action and raising a signal are async-signal-safe and
    // valid from any thread; the default action of SIGPIPE ends the process.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        libc::raise(libc::SIGPIPE);
    }
}

#[cfg(not(unix))]
fn raise_sigpipe() {
    // No SIGPIPE: the exit code a shell reports for it.
    std::process::exit(141);
}
