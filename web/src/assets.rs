//! The page and its files, built into the binary: the view loads nothing
//! from anywhere else and works with no network.

/// The page at `/`.
pub const INDEX_HTML: &str = include_str!("../assets/index.html");

/// A file of the page.
#[derive(Debug, Clone, Copy)]
pub struct File {
    /// Its media type.
    pub content_type: &'static str,
    /// Its content.
    pub body: &'static str,
}

/// The file at `path`, other than the page itself.
pub fn file(path: &str) -> Option<File> {
    let (content_type, body) = match path {
        "/app.js" => (
            "text/javascript; charset=utf-8",
            include_str!("../assets/app.js"),
        ),
        "/draw.js" => (
            "text/javascript; charset=utf-8",
            include_str!("../assets/draw.js"),
        ),
        "/style.css" => (
            "text/css; charset=utf-8",
            include_str!("../assets/style.css"),
        ),
        "/favicon.svg" | "/favicon.ico" => ("image/svg+xml", include_str!("../assets/favicon.svg")),
        _ => return None,
    };
    Some(File { content_type, body })
}
