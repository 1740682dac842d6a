//! The face's certificate store, in a folder the server owns (under its
//! data directory): `own/cert.der` (the self-signed application instance
//! certificate, made on the first start and again a month before it
//! expires), `private/private.pem` (its key,
//! readable by the owner only), `trusted/` and `rejected/` (client
//! certificates). Without a key pair the OPC UA server logs errors on
//! every connection and makes a `./pki` in the working directory.

use std::io;
use std::path::{Path, PathBuf};

use opcua::crypto::{CertificateStore, X509Data};
use opcua::types::{ApplicationDescription, DateTime};

/// The certificate, relative to the store.
pub const OWN_CERT: &str = "own/cert.der";
/// Its private key, relative to the store.
pub const OWN_KEY: &str = "private/private.pem";

/// Days a certificate must still be valid to be kept at a start; one
/// closer to its end (they are made for a year) is made anew, so that
/// clients never meet an expired one.
pub const RENEW_DAYS: i64 = 30;

/// Makes the store's key pair unless it has one valid for [`RENEW_DAYS`]
/// more; says whether it made it.
pub(crate) fn ensure_keypair(store: &Path, app: &ApplicationDescription) -> io::Result<bool> {
    let (cert, key) = (store.join(OWN_CERT), store.join(OWN_KEY));
    if key.is_file() && still_valid(&cert) {
        return Ok(false);
    }
    private_dir(&store.join("private"))?;
    std::fs::create_dir_all(store.join("own")).map_err(|e| named(e, store))?;
    let data: X509Data = app.clone().into();
    CertificateStore::create_certificate_and_key(&data, true, &cert, &key).map_err(|e| {
        io::Error::other(format!(
            "{}: cannot make the certificate: {e}",
            cert.display()
        ))
    })?;
    owner_only(&key)?;
    Ok(true)
}

/// Whether the certificate at `cert` reads and is valid for
/// [`RENEW_DAYS`] more.
fn still_valid(cert: &Path) -> bool {
    let Ok(cert) = CertificateStore::read_cert(cert) else {
        return false;
    };
    let now = DateTime::now().as_chrono();
    cert.not_after()
        .is_ok_and(|end| (end - now).num_days() >= RENEW_DAYS)
}

/// A folder readable by its owner only.
fn private_dir(dir: &Path) -> io::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| named(e, dir))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700))
            .map_err(|e| named(e, dir))?;
    }
    Ok(())
}

/// A file readable by its owner only.
fn owner_only(file: &Path) -> io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(file, std::fs::Permissions::from_mode(0o600))
            .map_err(|e| named(e, file))?;
    }
    #[cfg(not(unix))]
    let _ = file;
    Ok(())
}

/// An error naming the path it concerns.
fn named(e: io::Error, path: &Path) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// The certificate's path in `store`.
pub fn cert_path(store: &Path) -> PathBuf {
    store.join(OWN_CERT)
}
