//! How a command failed; the exit code follows from it.

/// How a command failed: the exit code follows.
#[derive(Debug)]
pub(crate) enum Failure {
    /// Bad input: exit 2.
    Input(anyhow::Error),
    /// Failure while running: exit 1.
    Runtime(anyhow::Error),
    /// The work ran but its answer is a failure (no plan, a check failed): exit 4.
    Check(anyhow::Error),
}
