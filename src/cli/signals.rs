//! SIGINT, SIGTERM and SIGHUP: remove the temporary files of atomic writes
//! in flight ([`crate::output::remove_temporaries`]), then end the way
//! the signal would have, so the shell still sees "killed by SIGINT".

/// Starts a thread that waits for a termination signal. Signal handlers
/// may do almost nothing safely; the thread is woken through signal-hook's
/// self-pipe and may take locks and remove files like any other code.
#[cfg(unix)]
pub fn remove_temporaries_on_termination() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        // Without the handler the process still ends on a signal; only its
        // temporary files stay behind, for a later run to remove.
        return;
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            crate::output::remove_temporaries();
            let _ = signal_hook::low_level::emulate_default_handler(sig);
            std::process::exit(128 + sig);
        }
    });
}

/// Elsewhere the process ends on a signal without removing anything.
#[cfg(not(unix))]
pub fn remove_temporaries_on_termination() {}
