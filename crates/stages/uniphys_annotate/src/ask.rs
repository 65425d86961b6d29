//! One question to the model with schema validation and one repair turn: the answer's JSON is
//! extracted from between the markers and validated; if either fails, the same request is sent
//! again with the previous answer and every violation listed (a new request, so a new cache key,
//! charged to the same ledger). If the repaired answer still fails, the stage gets
//! [`AnnotateError::InvalidAnswer`] with every violation: an answer is never dropped silently.

use serde_json::Value;
use uniphys_lvlm::{ChatRequest, CostLedger, LvlmClient, extract_marked_json};

use crate::prompt::repair_text;
use crate::validate::Violation;
use crate::{AnnotateError, AnnotateResult};

/// A validated answer and how it was obtained.
#[derive(Debug, Clone)]
pub struct Asked<T> {
    /// The validated answer.
    pub answer: T,
    /// The model that answered.
    pub model: String,
    /// The violations of the first answer, if a repair turn was needed.
    pub repaired: Vec<Violation>,
    /// Requests sent (1, or 2 with a repair turn), cache hits included.
    pub requests: u32,
}

/// The violations of an answer's text: extraction failures become one violation at `$`.
fn check<T>(
    text: &str,
    validate: &dyn Fn(&Value) -> Result<T, Vec<Violation>>,
) -> Result<T, Vec<Violation>> {
    match extract_marked_json(text) {
        Ok(value) => validate(&value),
        Err(error) => Err(vec![Violation {
            path: "$".to_owned(),
            message: error.to_string(),
        }]),
    }
}

/// Sends `request`, validates the answer with `validate`, and repairs it once if needed.
/// `subject` names the request in errors (`articulation of part 3`). When the repaired answer
/// is still invalid, both answers are dropped from the client's cache, so a retry of the stage
/// asks the model again instead of replaying them.
///
/// # Errors
/// [`AnnotateError::Lvlm`] if the client gives up (including the budget), and
/// [`AnnotateError::InvalidAnswer`] if the repaired answer is still invalid.
pub fn ask_validated<T>(
    client: &LvlmClient,
    ledger: &CostLedger,
    request: &ChatRequest,
    subject: &str,
    validate: &dyn Fn(&Value) -> Result<T, Vec<Violation>>,
) -> AnnotateResult<Asked<T>> {
    let first = client.complete(request, ledger)?;
    let violations = match check(&first.text, validate) {
        Ok(answer) => {
            return Ok(Asked {
                answer,
                model: first.model,
                repaired: Vec::new(),
                requests: 1,
            });
        }
        Err(violations) => violations,
    };
    let repair = ChatRequest {
        user_text: repair_text(&request.user_text, &first.text, &violations),
        purpose: format!("{} repair", request.purpose),
        ..request.clone()
    };
    let second = client.complete(&repair, ledger)?;
    match check(&second.text, validate) {
        Ok(answer) => Ok(Asked {
            answer,
            model: second.model,
            repaired: violations,
            requests: 2,
        }),
        Err(violations) => {
            // Best effort: an entry that cannot be removed only costs a repeated failure.
            client.forget(&first.digest).ok();
            client.forget(&second.digest).ok();
            Err(AnnotateError::InvalidAnswer {
                purpose: subject.to_owned(),
                violations,
            })
        }
    }
}
