//! What each object means to a user ([`uoi::Meaning`]): the text of the
//! object reference `docs/objects.md`.

mod otc;
mod tc;
