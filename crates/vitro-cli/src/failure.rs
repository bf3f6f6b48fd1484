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

impl From<vitro_tools::ToolError> for Failure {
    fn from(e: vitro_tools::ToolError) -> Failure {
        match e {
            vitro_tools::ToolError::Input(m) => Failure::Input(anyhow::anyhow!(m)),
            vitro_tools::ToolError::Runtime(m) => Failure::Runtime(anyhow::anyhow!(m)),
        }
    }
}
