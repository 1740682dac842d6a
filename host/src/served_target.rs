//! A server target with its options: `HOST:PORT` (or `localhost:PORT`,
//! a bare `PORT`) followed by options joined by commas, `token=TOKEN` and
//! `token_file=FILE`: the access token a server asks for
//! (`token_on_loopback`, `allow_remote`), as `addipos call` presents it.
//! Without an option the environment gives it: `ADDIPOS_TOKEN_FILE`, then
//! `ADDIPOS_TOKEN` (docs/host-api.md, "Targets").

use std::path::Path;

use uoi::tcp::AccessToken;

use crate::error::{Error, Result};

/// The environment variable holding the access token.
pub const TOKEN_ENV: &str = "ADDIPOS_TOKEN";

/// The environment variable naming a file that holds the access token
/// (it goes before [`TOKEN_ENV`]).
pub const TOKEN_FILE_ENV: &str = "ADDIPOS_TOKEN_FILE";

/// A server target: its address and the token to present.
#[derive(Debug, Clone)]
pub struct ServedTarget {
    /// The address as the target string gave it.
    pub address: String,
    /// The access token, if one is given.
    pub token: Option<AccessToken>,
}

impl ServedTarget {
    /// Reads `ADDRESS[,token=TOKEN][,token_file=FILE]`; a token file goes
    /// before a token, and an option before the environment.
    pub fn parse(text: &str) -> Result<Self> {
        let mut parts = text.split(',').map(str::trim);
        let address = parts.next().unwrap_or("").to_string();
        let (mut token, mut file) = (None, None);
        for option in parts.filter(|o| !o.is_empty()) {
            match option.split_once('=').map(|(k, v)| (k.trim(), v.trim())) {
                Some((k, v)) if k.eq_ignore_ascii_case("token") => token = Some(v.to_string()),
                Some((k, v)) if k.eq_ignore_ascii_case("token_file") => file = Some(v.to_string()),
                _ => {
                    let key = option.split('=').next().unwrap_or("");
                    return Err(Error::argument(format!(
                        "target `{address}`: option `{key}`: a server target takes \
                         token=TOKEN or token_file=FILE"
                    )));
                }
            }
        }
        let token = match (file, token) {
            (Some(f), _) => Some(token_of_file(Path::new(&f), "token_file")?),
            (None, Some(t)) => Some(token_of(&t, "token=")?),
            (None, None) => token_from_env()?,
        };
        Ok(Self { address, token })
    }
}

/// The token of the environment, if it gives one.
fn token_from_env() -> Result<Option<AccessToken>> {
    if let Some(f) = std::env::var_os(TOKEN_FILE_ENV).filter(|f| !f.is_empty()) {
        return token_of_file(Path::new(&f), TOKEN_FILE_ENV).map(Some);
    }
    match std::env::var(TOKEN_ENV) {
        Ok(t) if !t.trim().is_empty() => token_of(&t, TOKEN_ENV).map(Some),
        _ => Ok(None),
    }
}

/// A token text, checked; the error never repeats it.
fn token_of(text: &str, from: &str) -> Result<AccessToken> {
    AccessToken::new(text.trim()).map_err(|e| Error::argument(format!("{from}: {e}")))
}

/// The token a file holds (a regular file of at most 1 MiB).
fn token_of_file(path: &Path, from: &str) -> Result<AccessToken> {
    let text = emulator::read_settings_file(path)
        .map_err(|e| Error::argument(format!("{from} {}: {}", path.display(), e.0)))?;
    token_of(&text, &format!("{from} {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_give_the_token_and_an_unknown_one_is_named() {
        let t = ServedTarget::parse("127.0.0.1:1300, token=0123456789abcdef0123").unwrap();
        assert_eq!(t.address, "127.0.0.1:1300");
        assert_eq!(
            t.token.unwrap().as_bytes(),
            b"0123456789abcdef0123".as_slice()
        );
        let e = ServedTarget::parse("1300,colour=red").unwrap_err();
        assert!(e.message().contains("`colour`"), "{e}");
        let e = ServedTarget::parse("1300,token=short").unwrap_err();
        assert!(!e.message().contains("short"), "{e}");
    }
}
