//! # web-view — a live web view of the emulator (`addipos serve --web`)
//!
//! One page at `/` that shows what the served emulator does while a host
//! program runs: the position of every axis, each group's STATUS and
//! ERROR with their bits named, the spooler, the tool entries in use,
//! OTC, the path (spooled elements and executed trail) and who is
//! connected; kept current by server-sent events at most 20 times a
//! second, nothing sent while nothing changes. `/state` gives the same
//! state as JSON (docs/web.md).
//!
//! The view is read-only: it looks at the emulator through the object
//! server's [`CoreHandle`](uoi::tcp::CoreHandle) between two requests and
//! changes nothing; any method but GET is refused. It costs the emulator
//! nothing while no page is open.
//!
//! * [`face`]: `WebFace`, bound and served, its settings and limits;
//! * [`routes`]: which answer a request gets;
//! * [`http`]: the request head and the answers, with the security
//!   headers every answer carries;
//! * [`events`]: one page's event stream;
//! * [`hub`]: what the pages share;
//! * [`sampler`]: the one task that looks at the emulator;
//! * [`snapshot`]: the state taken in one look (the JSON of `/state`);
//! * [`path`]: the spooled elements and the executed trail, bounded;
//! * [`assets`]: the page's files, built in.

pub mod assets;
pub mod events;
pub mod face;
pub mod http;
pub mod hub;
pub mod path;
pub mod routes;
pub mod sampler;
pub mod snapshot;

pub use face::{WebConfig, WebError, WebFace, MAX_CONNECTIONS, MAX_VIEWERS};
pub use snapshot::Snapshot;
