//! The segmenter and candidate generator a run uses: SAM-compatible and PartField-compatible
//! services when their settings are given, else the built-in ones.

use uniphys_vision::{ClientConfig, PartFieldClient, SamClient};

use crate::candidates::PartFieldGenerator;
use crate::segment::SamSegmenter;
use crate::{BuiltinSegmenter, CandidateGenerator, DecomposeResult, GeometricGenerator, Segmenter};

/// The segmenter: a SAM-compatible service at `sam`, or the built-in render-space segmenter.
///
/// # Errors
/// [`DecomposeError::Vision`](crate::DecomposeError::Vision) for invalid client settings.
pub fn segmenter_for(sam: Option<&ClientConfig>) -> DecomposeResult<Box<dyn Segmenter>> {
    Ok(match sam {
        Some(config) => Box::new(SamSegmenter::new(SamClient::new(config.clone())?)),
        None => Box::new(BuiltinSegmenter::default()),
    })
}

/// The candidate generator: a PartField-compatible service at `partfield`, or the built-in
/// geometric generator.
///
/// # Errors
/// [`DecomposeError::Vision`](crate::DecomposeError::Vision) for invalid client settings.
pub fn generator_for(
    partfield: Option<&ClientConfig>,
) -> DecomposeResult<Box<dyn CandidateGenerator>> {
    Ok(match partfield {
        Some(config) => Box::new(PartFieldGenerator::new(PartFieldClient::new(
            config.clone(),
        )?)),
        None => Box::new(GeometricGenerator::default()),
    })
}
