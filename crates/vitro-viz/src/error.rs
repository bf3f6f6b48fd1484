//! Why the viewer could not start or serve.

/// An error a source reports (its controller failed, its state is inconsistent).
pub type SourceError = Box<dyn std::error::Error + Send + Sync>;

/// Why the viewer could not start or serve.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// The address could not be bound.
    #[error("cannot listen: {0}")]
    Bind(#[source] std::io::Error),
    /// The server failed while serving.
    #[error("server failed: {0}")]
    Serve(#[source] std::io::Error),
    /// The simulation thread could not be started.
    #[error("cannot start the simulation thread: {0}")]
    Thread(#[source] std::io::Error),
    /// The requested speed is out of range.
    #[error("{0}")]
    Speed(#[from] vitro::sim::ControlError),
    /// The recording could not be read.
    #[error("cannot read the recording: {0}")]
    Source(#[source] SourceError),
}
