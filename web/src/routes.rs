//! Which answer a request gets: the page and its files (built into the
//! binary), `/state`, the event stream; any method but GET refused with
//! `405`, a missing token with `401`, anything else `404`.

use crate::assets;
use crate::http::{query_value, Answer, Head};

/// What a request asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Route {
    /// A fixed answer (a file of the page, or a refusal).
    Fixed(Answer),
    /// The state as JSON.
    State,
    /// The event stream.
    Events,
}

/// The route of `head`; `token_ok`: whether the request may see the
/// machine's state (its peer needs no token, or it presented the right
/// one).
pub fn route(head: &Head, token_ok: impl Fn(&str) -> bool, needs_token: bool) -> Route {
    if head.method != "GET" {
        let mut a = Answer::error(
            "405 Method Not Allowed",
            "the view is read-only: only GET is served",
        );
        a.allow = Some("GET");
        return Route::Fixed(a);
    }
    if let Some(file) = assets::file(&head.path) {
        return Route::Fixed(Answer::ok(file.content_type, file.body));
    }
    let data = matches!(
        head.path.as_str(),
        "/" | "/index.html" | "/state" | "/events"
    );
    if !data {
        return Route::Fixed(Answer::error("404 Not Found", "no such page"));
    }
    if needs_token {
        let presented = head
            .bearer
            .clone()
            .or_else(|| query_value(&head.query, "token"));
        if !presented.is_some_and(|t| token_ok(&t)) {
            return Route::Fixed(Answer::error(
                "401 Unauthorized",
                "this server's access token is needed: add ?token=TOKEN to the address",
            ));
        }
    }
    match head.path.as_str() {
        "/state" => Route::State,
        "/events" => Route::Events,
        _ => Route::Fixed(Answer::ok("text/html; charset=utf-8", assets::INDEX_HTML)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head(method: &str, target: &str) -> Head {
        let (path, query) = target.split_once('?').unwrap_or((target, ""));
        Head {
            method: method.into(),
            path: path.into(),
            query: query.into(),
            bearer: None,
        }
    }

    #[test]
    fn only_get_and_only_with_the_token_where_one_is_needed() {
        let ok = |t: &str| t == "s3cret-token";
        for m in ["POST", "PUT", "DELETE", "PATCH", "OPTIONS"] {
            let Route::Fixed(a) = route(&head(m, "/state"), ok, false) else {
                panic!("{m} served");
            };
            assert_eq!(a.status, "405 Method Not Allowed");
        }
        assert_eq!(route(&head("GET", "/state"), ok, false), Route::State);
        let Route::Fixed(a) = route(&head("GET", "/state"), ok, true) else {
            panic!("served without the token");
        };
        assert_eq!(a.status, "401 Unauthorized");
        let with = head("GET", "/events?token=s3cret-token");
        assert_eq!(route(&with, ok, true), Route::Events);
        let Route::Fixed(a) = route(&head("GET", "/app.js"), ok, true) else {
            panic!("a file");
        };
        assert_eq!(a.status, "200 OK");
        let Route::Fixed(a) = route(&head("GET", "/nothing"), ok, false) else {
            panic!("404");
        };
        assert_eq!(a.status, "404 Not Found");
    }
}
