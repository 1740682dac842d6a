//! The server's access token on disk: `<data_dir>/access-token`, read if it
//! is there, else generated (random, 32 hex digits) and written readable
//! by its owner only. Clients pass the same text with `--token-file`,
//! `--token` or `ADDIPOS_TOKEN`.

use std::fmt::Write as _;
use std::io::{self, Write as _};
use std::path::{Path, PathBuf};

use uoi::tcp::AccessToken;

/// The token file's name in the data directory.
const TOKEN_FILE: &str = "access-token";

/// Random bytes in a generated token (twice as many hex digits).
const TOKEN_BYTES: usize = 16;

/// The server's token and where it is kept.
#[derive(Debug, Clone)]
pub struct TokenFile {
    /// The token.
    pub token: AccessToken,
    /// The file it is kept in.
    pub path: PathBuf,
    /// Whether this start generated it.
    pub created: bool,
}

/// Reads the token from `data_dir`, or generates and writes one there
/// (creating the folder) if the file does not exist.
pub fn load_or_create(data_dir: &Path) -> io::Result<TokenFile> {
    let path = data_dir.join(TOKEN_FILE);
    match std::fs::read_to_string(&path) {
        Ok(text) => {
            let token = parse(&text, &path)?;
            return Ok(TokenFile {
                token,
                path,
                created: false,
            });
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => {}
        Err(e) => return Err(named(e, &path)),
    }
    std::fs::create_dir_all(data_dir).map_err(|e| named(e, data_dir))?;
    let text = generate()?;
    write_private(&path, &text).map_err(|e| named(e, &path))?;
    Ok(TokenFile {
        token: parse(&text, &path)?,
        path,
        created: true,
    })
}

/// Reads a client's token file.
pub fn read_token_file(path: &Path) -> io::Result<AccessToken> {
    let text = std::fs::read_to_string(path).map_err(|e| named(e, path))?;
    parse(&text, path)
}

/// A token from the text of `path`.
fn parse(text: &str, path: &Path) -> io::Result<AccessToken> {
    AccessToken::new(text).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{}: {e}", path.display()),
        )
    })
}

/// An error naming the file it concerns.
fn named(e: io::Error, path: &Path) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// A fresh random token: hex digits of bytes from the system's source.
fn generate() -> io::Result<String> {
    let mut bytes = [0u8; TOKEN_BYTES];
    getrandom::fill(&mut bytes).map_err(io::Error::other)?;
    let mut text = String::with_capacity(2 * TOKEN_BYTES + 1);
    for b in bytes {
        let _ = write!(text, "{b:02x}");
    }
    text.push('\n');
    Ok(text)
}

/// Writes a new file readable by its owner only (mode 0600 on Unix);
/// fails if it exists.
fn write_private(path: &Path, text: &str) -> io::Result<()> {
    let mut opts = std::fs::OpenOptions::new();
    opts.write(true).create_new(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::mode(&mut opts, 0o600);
    let mut f = opts.open(path)?;
    f.write_all(text.as_bytes())?;
    f.sync_all()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("addipos-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn generated_once_private_then_read_back() {
        let dir = temp_dir("token").join("data");
        let first = load_or_create(&dir).expect("created");
        assert!(first.created);
        assert_eq!(first.path, dir.join(TOKEN_FILE));
        let text = std::fs::read_to_string(&first.path).expect("file");
        assert_eq!(text.trim().len(), 32);
        assert!(text.trim().bytes().all(|b| b.is_ascii_hexdigit()));
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&first.path)
                .expect("meta")
                .permissions()
                .mode();
            assert_eq!(mode & 0o777, 0o600);
        }
        let again = load_or_create(&dir).expect("read");
        assert!(!again.created);
        assert_eq!(again.token, first.token);
        assert_eq!(read_token_file(&first.path).expect("client"), first.token);
        let other = load_or_create(&temp_dir("token2")).expect("created");
        assert_ne!(other.token, first.token);
    }

    #[test]
    fn a_bad_token_file_is_named() {
        let dir = temp_dir("badtoken");
        std::fs::create_dir_all(&dir).expect("dir");
        std::fs::write(dir.join(TOKEN_FILE), "secret\n").expect("write");
        let err = load_or_create(&dir).expect_err("too short");
        assert!(err.to_string().contains(TOKEN_FILE), "{err}");
    }
}
