//! Who may use the face. Open (programs on this machine only): anonymous
//! users on the endpoint without security. Guarded (reachable from other
//! machines): no anonymous user; the client logs in with any user name
//! and the server's access token as password, on the endpoint with
//! Basic256Sha256 Sign&Encrypt only, so the token never travels in clear.

use async_trait::async_trait;
use opcua::crypto::SecurityPolicy;
use opcua::server::authenticator::{
    user_pass_security_policy_id, user_pass_security_policy_uri, AuthManager, Password, UserToken,
};
use opcua::server::{ServerEndpoint, ANONYMOUS_USER_TOKEN_ID};
use opcua::types::{
    Error, MessageSecurityMode, StatusCode, UAString, UserTokenPolicy, UserTokenType,
};
use uoi::tcp::AccessToken;

/// The policy id of the anonymous user token.
const ANONYMOUS_POLICY: &str = "anonymous";

/// The path of the one endpoint.
pub(crate) const ENDPOINT_PATH: &str = "/";

/// The face's endpoint: (id, security policy, mode).
pub(crate) fn endpoint(guarded: bool) -> (&'static str, ServerEndpoint) {
    if guarded {
        let e = ServerEndpoint::new(
            ENDPOINT_PATH,
            SecurityPolicy::Basic256Sha256,
            MessageSecurityMode::SignAndEncrypt,
            &[],
        );
        ("basic256sha256_sign_encrypt", e)
    } else {
        let e = ServerEndpoint::new_none(ENDPOINT_PATH, &[ANONYMOUS_USER_TOKEN_ID.to_string()]);
        ("none", e)
    }
}

/// Lets users in: anonymous ones when there is no token, else those who
/// present it as their password.
pub(crate) struct TokenGate {
    token: Option<AccessToken>,
}

impl TokenGate {
    /// The gate of `token` (`None`: open).
    pub fn new(token: Option<AccessToken>) -> Self {
        Self { token }
    }
}

#[async_trait]
impl AuthManager for TokenGate {
    async fn authenticate_anonymous_token(&self, _endpoint: &ServerEndpoint) -> Result<(), Error> {
        match self.token {
            None => Ok(()),
            // The status the library answers itself for a token of a type
            // the endpoint does not offer, as docs/opcua.md says.
            Some(_) => Err(Error::new(
                StatusCode::BadIdentityTokenInvalid,
                "anonymous users are refused: log in with the access token as password",
            )),
        }
    }

    async fn authenticate_username_identity_token(
        &self,
        _endpoint: &ServerEndpoint,
        username: &str,
        password: &Password,
    ) -> Result<UserToken, Error> {
        match &self.token {
            Some(token) if token.matches(password.get().as_bytes()) => {
                Ok(UserToken(username.to_string()))
            }
            Some(_) => {
                tracing::warn!(user = username, "OPC UA login with a wrong access token");
                Err(Error::new(
                    StatusCode::BadUserAccessDenied,
                    "the password is not the server's access token",
                ))
            }
            None => Err(Error::new(
                StatusCode::BadIdentityTokenInvalid,
                "log in anonymously",
            )),
        }
    }

    fn user_token_policies(&self, endpoint: &ServerEndpoint) -> Vec<UserTokenPolicy> {
        let policy = match self.token {
            None => UserTokenPolicy {
                policy_id: UAString::from(ANONYMOUS_POLICY),
                token_type: UserTokenType::Anonymous,
                issued_token_type: UAString::null(),
                issuer_endpoint_url: UAString::null(),
                security_policy_uri: UAString::null(),
            },
            Some(_) => UserTokenPolicy {
                policy_id: user_pass_security_policy_id(endpoint),
                token_type: UserTokenType::UserName,
                issued_token_type: UAString::null(),
                issuer_endpoint_url: UAString::null(),
                security_policy_uri: user_pass_security_policy_uri(endpoint),
            },
        };
        vec![policy]
    }
}
