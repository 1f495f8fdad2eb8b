//! The capture's runtime folder: Mesa wants a valid `XDG_RUNTIME_DIR`, and a
//! headless capture gets a private one when there is none (the commands
//! that render create it before anything else runs; it is removed when the
//! run ends, or by the interrupt handler).

/// The runtime folder's name before the process id.
const RUNTIME_PREFIX: &str = "ufcsr-runtime-";

/// A private runtime folder for Mesa, removed when the program ends.
///
/// Mesa's window-system probe prints `error: XDG_RUNTIME_DIR is invalid or
/// not set` (twice) while it looks for a display, which a headless capture
/// never uses; a run without a valid `XDG_RUNTIME_DIR` gets its own 0700
/// folder, so the message a user sees is only ever about their capture.
pub(crate) struct PrivateRuntimeDir(Option<std::path::PathBuf>);

impl PrivateRuntimeDir {
    /// The folder, when the run needs one (see above); call it before any
    /// other thread starts.
    #[allow(unsafe_code)] // std::env::set_var, before any other thread exists
    pub(crate) fn create() -> PrivateRuntimeDir {
        let valid =
            std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|dir| std::path::Path::new(&dir).is_dir());
        if valid || cfg!(not(unix)) {
            return PrivateRuntimeDir(None);
        }
        // Those of killed captures (SIGKILL runs no handler) go first.
        ufcsr::files::remove_dead_runs(&std::env::temp_dir(), RUNTIME_PREFIX);
        let dir = std::env::temp_dir().join(format!("{RUNTIME_PREFIX}{}", std::process::id()));
        if ufcsr::files::create_private_dir(&dir).is_err() {
            return PrivateRuntimeDir(None);
        }
        // SAFETY: `crate::program::main` calls this right after parsing the
        // command line, before any other thread exists (the interrupt
        // handler, the worker threads and the GPU's threads start later).
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
        ufcsr::files::remove_on_interrupt(&dir);
        PrivateRuntimeDir(Some(dir))
    }
}

impl Drop for PrivateRuntimeDir {
    fn drop(&mut self) {
        // Our own folder, made above inside the temporary folder.
        if let Some((dir, parent)) = self.0.as_ref().and_then(|dir| Some((dir, dir.parent()?))) {
            let _ = ufcsr::files::remove_inside(parent, dir);
        }
    }
}
