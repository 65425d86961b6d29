//! A recorded-answer HTTP/1.1 server for tests of the clients of external model services
//! (SAM-compatible masks, PartField-compatible features, OpenAI-compatible LVLMs).
//!
//! It speaks plain HTTP/1.1 on `std::net` with one thread per connection: keep-alive,
//! `Content-Length` and chunked request bodies, `Expect: 100-continue`, bodies of tens of MB.
//! A [`Recording`] lists [`Exchange`]s matched by method, path and body substrings; each plays
//! its [`Reply`]s in order (the last one repeats), with delays and [`Fault`]s (hang, truncated
//! body, close without reply). Requests no exchange matches get 501 with a JSON body naming
//! them. Tests can also answer with a closure ([`ReplayServer::start_with`]).
//!
//! The server records every request ([`ReplayServer::requests`]) and the largest number
//! answered at once ([`ReplayServer::max_in_flight`]). The `uniphys-replay` binary serves a
//! recording file and prints its URL.
//!
//! Recording JSON:
//! ```json
//! { "exchanges": [ { "method": "POST", "path": "/v1/masks", "body_contains": ["\"width\":32"],
//!     "replies": [ { "status": 429, "headers": {"Retry-After": "0"}, "body": "busy" },
//!                  { "fault": {"kind": "truncate", "keep_bytes": 5}, "json": {"masks": []} },
//!                  { "status": 200, "json": {"masks": []}, "delay_ms": 10 } ] } ] }
//! ```

mod error;
mod http;
mod recording;
mod reply;
mod server;

pub use error::{ReplayError, ReplayResult};
pub use recording::{Exchange, Recording};
pub use reply::{Fault, Reply};
pub use server::{RecordedRequest, ReplayServer, Responder};
