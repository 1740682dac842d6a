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
use opcua::types::DateTime;

/// The certificate, relative to the store.
pub const OWN_CERT: &str = "own/cert.der";
/// Its private key, relative to the store.
pub const OWN_KEY: &str = "private/private.pem";

/// Days a certificate must still be valid to be kept at a start; one
/// closer to its end (they are made for a year) is made anew, so that
/// clients never meet an expired one.
pub const RENEW_DAYS: i64 = 30;

/// Size of the certificate's RSA key, bits.
const KEY_BITS: u32 = 2048;

/// The subject of the server's certificate beside its common name (the
/// application's name): each part left empty is left out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CertSubject {
    /// Organisation (O).
    pub organization: String,
    /// Organisational unit (OU).
    pub unit: String,
    /// Country (C), two letters.
    pub country: String,
    /// State or province (ST).
    pub state: String,
}

impl Default for CertSubject {
    fn default() -> Self {
        Self {
            organization: "addipos-tc".into(),
            unit: String::new(),
            country: String::new(),
            state: String::new(),
        }
    }
}

/// What the certificate names.
pub(crate) struct Names<'a> {
    /// The common name (CN).
    pub application_name: &'a str,
    /// The application URI (the first subject alternative name).
    pub application_uri: &'a str,
    /// The host names clients connect with.
    pub hosts: &'a [String],
    /// The rest of the subject.
    pub subject: &'a CertSubject,
}

/// The certificate's data: the subject from `names`, and as alternative
/// names the application URI, every host name, `localhost` and the
/// loopback addresses, and the addresses of this machine's names, each
/// once.
fn x509_data(names: &Names<'_>) -> X509Data {
    let mut hosts: Vec<String> = Vec::new();
    let mut add = |h: &str| {
        let h = h.trim_start_matches('[').trim_end_matches(']');
        if !h.is_empty() && !hosts.iter().any(|k| k.eq_ignore_ascii_case(h)) {
            hosts.push(h.to_string());
        }
    };
    names.hosts.iter().for_each(|h| add(h));
    ["localhost", "127.0.0.1", "::1"]
        .into_iter()
        .for_each(&mut add);
    for name in X509Data::computer_hostnames() {
        add(&name);
        if let Ok(addrs) = std::net::ToSocketAddrs::to_socket_addrs(&(name.as_str(), 0)) {
            addrs.for_each(|a| add(&a.ip().to_string()));
        }
    }
    let alt_host_names =
        X509Data::alt_host_names(names.application_uri, Some(hosts), false, false, false);
    let s = names.subject;
    X509Data {
        key_size: KEY_BITS,
        common_name: names.application_name.into(),
        organization: s.organization.clone(),
        organizational_unit: s.unit.clone(),
        country: s.country.clone(),
        state: s.state.clone(),
        alt_host_names,
        certificate_duration_days: 365,
    }
}

/// Makes the store's key pair unless it has one valid for [`RENEW_DAYS`]
/// more; says whether it made it.
pub(crate) fn ensure_keypair(store: &Path, names: &Names<'_>) -> io::Result<bool> {
    let (cert, key) = (store.join(OWN_CERT), store.join(OWN_KEY));
    if key.is_file() && still_valid(&cert) {
        return Ok(false);
    }
    private_dir(&store.join("private"))?;
    std::fs::create_dir_all(store.join("own")).map_err(|e| named(e, store))?;
    let data = x509_data(names);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_subject_of_the_settings_and_each_alternative_name_once() {
        let subject = CertSubject {
            country: "DE".into(),
            ..CertSubject::default()
        };
        let hosts = ["127.0.0.1".to_string(), "LocalHost".into(), "[::1]".into()];
        let data = x509_data(&Names {
            application_name: "app",
            application_uri: "urn:app",
            hosts: &hosts,
            subject: &subject,
        });
        assert_eq!(
            (data.common_name.as_str(), data.organization.as_str()),
            ("app", "addipos-tc")
        );
        assert_eq!((data.country.as_str(), data.state.as_str()), ("DE", ""));
        let names: Vec<String> = data.alt_host_names.iter().collect();
        assert_eq!(names[..4], ["urn:app", "127.0.0.1", "LocalHost", "::1"]);
        let mut lower: Vec<_> = names.iter().map(|n| n.to_lowercase()).collect();
        lower.sort();
        lower.dedup();
        assert_eq!(lower.len(), names.len(), "{names:?}");
    }
}
