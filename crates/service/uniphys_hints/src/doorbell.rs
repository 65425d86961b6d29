//! Doorbells (wake-up hints per stage) and event streams, both fed by a background task that
//! keeps a pub/sub subscription alive.
//!
//! The task is started when the doorbell or stream is made (so rings are heard from then on, not
//! only from the first `wait`), reconnects on its own after a failure, and ends when its
//! [`Doorbell`] or [`EventStream`] is dropped. While it cannot subscribe, `wait` simply runs out
//! its time: the caller's poll is the guarantee, the ring only makes it sooner.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use futures::StreamExt;
use tokio::sync::{broadcast, mpsc};
use tokio::time::{Instant, sleep, timeout};

/// What ended a [`Doorbell::wait`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wake {
    /// One of the doorbell's stages was rung (possibly several times, coalesced): claim now.
    Rung,
    /// Nothing was heard within the wait (or the hint store is down): poll as usual.
    Timeout,
}

/// Listens for rings on a set of stages. Made by [`crate::Hints::doorbell`].
#[derive(Debug)]
pub struct Doorbell {
    rx: mpsc::Receiver<String>,
    subscribed: Arc<AtomicBool>,
}

impl Doorbell {
    /// True while the doorbell's subscription is live (always, for the local backend). Rings made
    /// while it is false are not heard; the caller's poll covers them.
    pub fn is_subscribed(&self) -> bool {
        self.subscribed.load(Ordering::Relaxed)
    }

    /// Waits at most `max` for a ring on one of this doorbell's stages.
    ///
    /// Rings heard since the last call count (they are coalesced into one [`Wake::Rung`]), so a
    /// ring that arrives while the worker is busy is not lost before its next claim.
    pub async fn wait(&mut self, max: Duration) -> Wake {
        match timeout(max, self.rx.recv()).await {
            Ok(Some(_)) => Wake::Rung,
            // `None` cannot happen while `self` holds the receiver and the task holds the sender
            // until the receiver is gone; treat it as silence all the same.
            Ok(None) => {
                sleep(max).await;
                Wake::Timeout
            }
            Err(_) => Wake::Timeout,
        }
    }
}

/// Receives application events published on one channel. Made by
/// [`crate::Hints::subscribe_events`]. Best effort: events published while the subscription is
/// down, or while this stream lags more than its buffer behind, are dropped.
#[derive(Debug)]
pub struct EventStream {
    rx: mpsc::Receiver<String>,
    subscribed: Arc<AtomicBool>,
}

impl EventStream {
    /// True while the stream's subscription is live (always, for the local backend).
    pub fn is_subscribed(&self) -> bool {
        self.subscribed.load(Ordering::Relaxed)
    }

    /// The next event's payload, or `None` when nothing arrived within `max`.
    pub async fn next(&mut self, max: Duration) -> Option<String> {
        match timeout(max, self.rx.recv()).await {
            Ok(Some(payload)) => Some(payload),
            Ok(None) => {
                sleep(max).await;
                None
            }
            Err(_) => None,
        }
    }
}

/// How many undelivered events an [`EventStream`] keeps.
const EVENT_BUFFER: usize = 256;

/// Makes a doorbell: a buffer of one, so rings coalesce.
pub(crate) fn doorbell(source: Source, channels: Vec<String>) -> Doorbell {
    let (rx, subscribed) = spawn_forwarder(source, channels, 1, true);
    Doorbell { rx, subscribed }
}

/// Makes an event stream on one channel.
pub(crate) fn event_stream(source: Source, channel: String) -> EventStream {
    let (rx, subscribed) = spawn_forwarder(source, vec![channel], EVENT_BUFFER, false);
    EventStream { rx, subscribed }
}

/// Where messages come from.
pub(crate) enum Source {
    /// A Redis server: one pub/sub connection per subscriber.
    Redis {
        /// The client to open pub/sub connections with.
        client: redis::Client,
        /// Bound on connecting and subscribing.
        connect_timeout: Duration,
        /// Pause after a failed or lost subscription before the next try.
        resubscribe_after: Duration,
    },
    /// The in-process bus of [`crate::Hints::local`].
    Local(broadcast::Receiver<(Arc<str>, Arc<str>)>),
}

/// Starts the task that moves messages for `channels` into a bounded channel, dropping what does
/// not fit, and returns its receiving end and the flag telling whether the subscription is live.
/// With `wake_on_lag`, messages the local bus lost count as one (empty) message.
fn spawn_forwarder(
    source: Source,
    channels: Vec<String>,
    buffer: usize,
    wake_on_lag: bool,
) -> (mpsc::Receiver<String>, Arc<AtomicBool>) {
    let (tx, rx) = mpsc::channel(buffer);
    let subscribed = Arc::new(AtomicBool::new(false));
    match source {
        Source::Redis {
            client,
            connect_timeout,
            resubscribe_after,
        } => {
            tokio::spawn(forward_redis(
                client,
                channels,
                connect_timeout,
                resubscribe_after,
                tx,
                subscribed.clone(),
            ));
        }
        Source::Local(bus) => {
            subscribed.store(true, Ordering::Relaxed);
            tokio::spawn(forward_local(bus, channels, tx, wake_on_lag));
        }
    }
    (rx, subscribed)
}

/// Subscribes, forwards until the connection ends, waits, subscribes again; until `tx` closes.
async fn forward_redis(
    client: redis::Client,
    channels: Vec<String>,
    connect_timeout: Duration,
    resubscribe_after: Duration,
    tx: mpsc::Sender<String>,
    subscribed_flag: Arc<AtomicBool>,
) {
    loop {
        let subscribed = tokio::select! {
            () = tx.closed() => return,
            subscribed = timeout(connect_timeout, subscribe(&client, &channels)) => subscribed,
        };
        if let Ok(Ok(mut messages)) = subscribed {
            subscribed_flag.store(true, Ordering::Relaxed);
            loop {
                let message = tokio::select! {
                    () = tx.closed() => return,
                    message = messages.next() => message,
                };
                let Some(message) = message else {
                    subscribed_flag.store(false, Ordering::Relaxed);
                    break;
                };
                let payload = String::from_utf8_lossy(message.get_payload_bytes()).into_owned();
                // A full buffer means the receiver has not caught up: drop (rings coalesce).
                if let Err(mpsc::error::TrySendError::Closed(_)) = tx.try_send(payload) {
                    return;
                }
            }
        }
        let retry_at = Instant::now() + resubscribe_after;
        tokio::select! {
            () = tx.closed() => return,
            () = tokio::time::sleep_until(retry_at) => {}
        }
    }
}

/// Opens a pub/sub connection and subscribes it to `channels`.
async fn subscribe(
    client: &redis::Client,
    channels: &[String],
) -> redis::RedisResult<redis::aio::PubSubStream> {
    let mut pubsub = client.get_async_pubsub().await?;
    pubsub.subscribe(channels).await?;
    Ok(pubsub.into_on_message())
}

/// Forwards the in-process bus's messages for `channels`; a lag (lost messages) counts as one.
async fn forward_local(
    mut bus: broadcast::Receiver<(Arc<str>, Arc<str>)>,
    channels: Vec<String>,
    tx: mpsc::Sender<String>,
    wake_on_lag: bool,
) {
    loop {
        let received = tokio::select! {
            () = tx.closed() => return,
            received = bus.recv() => received,
        };
        let payload = match received {
            Ok((channel, payload)) => {
                if !channels.iter().any(|c| **c == *channel) {
                    continue;
                }
                payload.to_string()
            }
            Err(broadcast::error::RecvError::Lagged(_)) if wake_on_lag => String::new(),
            Err(broadcast::error::RecvError::Lagged(_)) => continue,
            Err(broadcast::error::RecvError::Closed) => return,
        };
        if let Err(mpsc::error::TrySendError::Closed(_)) = tx.try_send(payload) {
            return;
        }
    }
}
