//! Group commit of completions: many workers' [`Completer::complete`] calls share one
//! transaction ([`QueueStore::complete_many`]).
//!
//! A background task takes every completion waiting when it is free (up to `max_batch`), yields
//! once so that completions made at the same moment join them, and writes them together;
//! completions that arrive while a batch is written form the next one. An idle queue pays no
//! timer (a lone completion is written at once); a busy one writes fewer, larger transactions. Fencing is unchanged: each completion gets its own result.

use serde_json::Value;
use tokio::sync::{mpsc, oneshot};

use crate::store::Completion;
use crate::{CompleteOutcome, Lease, QueueError, QueueResult, QueueStore, StageCost};

/// Completions written in one transaction at most, by default.
pub const DEFAULT_COMPLETION_BATCH: usize = 256;

/// A request and where its answer goes.
type Request = (Completion, oneshot::Sender<QueueResult<CompleteOutcome>>);

/// A handle to the task that writes completions in batches. Cloning shares the task; it ends
/// when the last handle is dropped, after writing what it holds.
#[derive(Clone, Debug)]
pub struct Completer {
    requests: mpsc::UnboundedSender<Request>,
}

impl Completer {
    /// Starts the batching task on the current tokio runtime; at most `max_batch` completions
    /// (at least 1) go into one transaction.
    #[must_use]
    pub fn spawn(store: QueueStore, max_batch: usize) -> Self {
        let (requests, inbox) = mpsc::unbounded_channel();
        tokio::spawn(write_batches(store, inbox, max_batch.max(1)));
        Self { requests }
    }

    /// Completes a held run as [`QueueStore::complete`] does, written together with whatever
    /// other completions are waiting.
    pub async fn complete(
        &self,
        lease: &Lease,
        output_manifest: &Value,
        cost: &StageCost,
    ) -> QueueResult<CompleteOutcome> {
        let (reply, answer) = oneshot::channel();
        let completion = Completion {
            lease: *lease,
            output_manifest: output_manifest.clone(),
            cost: cost.clone(),
        };
        self.requests
            .send((completion, reply))
            .map_err(|_| stopped())?;
        answer.await.map_err(|_| stopped())?
    }
}

fn stopped() -> QueueError {
    QueueError::Invalid("the completer's task has stopped (its runtime shut down)".to_owned())
}

async fn write_batches(
    store: QueueStore,
    mut inbox: mpsc::UnboundedReceiver<Request>,
    max_batch: usize,
) {
    let mut batch: Vec<Request> = Vec::with_capacity(max_batch);
    while inbox.recv_many(&mut batch, max_batch).await > 0 {
        // Completions made together (a claimed batch finishing at once) wake this task at the
        // first of them: let the rest be sent before writing.
        if batch.len() < max_batch {
            tokio::task::yield_now().await;
            while batch.len() < max_batch {
                match inbox.try_recv() {
                    Ok(request) => batch.push(request),
                    Err(_) => break,
                }
            }
        }
        let (completions, replies): (Vec<Completion>, Vec<_>) = batch.drain(..).unzip();
        match store.complete_many(&completions).await {
            Ok(results) => {
                for (reply, result) in replies.into_iter().zip(results) {
                    // A caller that stopped waiting no longer needs its answer.
                    let _ = reply.send(result);
                }
            }
            // The transaction failed as a whole: each completion is tried on its own, so each
            // caller gets its own error (and one bad completion does not sink the others).
            Err(_) => {
                for (completion, reply) in completions.into_iter().zip(replies) {
                    let result = store
                        .complete(
                            &completion.lease,
                            &completion.output_manifest,
                            &completion.cost,
                        )
                        .await;
                    let _ = reply.send(result);
                }
            }
        }
    }
}
