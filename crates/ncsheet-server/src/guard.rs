//! Who may talk to the workbench: the browser tab that was given the token, through
//! 127.0.0.1 or localhost at the server's own port. A page of another site can make the
//! browser send requests here (or rename itself to 127.0.0.1 by DNS rebinding): its Origin or
//! Host header gives it away, and it cannot know the token.

use std::hash::{BuildHasher, Hasher};

/// The header the page's API calls carry the token in (the page itself takes it as `?t=`).
pub const TOKEN_HEADER: &str = "x-ncsheet-token";

/// Why a request is refused (a 403 to the caller).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Denied {
    Host,
    Origin,
    Token,
}

impl Denied {
    pub fn message(self) -> &'static str {
        match self {
            Denied::Host => "forbidden: the Host header names another server",
            Denied::Origin => "forbidden: the request comes from another site",
            Denied::Token => {
                "forbidden: the request lacks the workbench's token (open the URL `ncsheet serve` printed)"
            }
        }
    }
}

/// What a request says about where it comes from.
pub struct Claims<'a> {
    pub host: Option<&'a str>,
    pub origin: Option<&'a str>,
    /// The token from the header or, for the page, from the query.
    pub token: Option<&'a str>,
}

/// The checks of one server: its port and token.
#[derive(Clone)]
pub struct Guard {
    port: u16,
    token: String,
}

impl Guard {
    pub fn new(port: u16, token: String) -> Guard {
        Guard { port, token }
    }

    pub fn token(&self) -> &str {
        &self.token
    }

    /// Admits a request whose Host is this server, whose Origin (when the browser sends one)
    /// is this server, and that carries the token.
    pub fn admit(&self, claims: &Claims) -> Result<(), Denied> {
        if !claims.host.is_some_and(|h| self.is_own_authority(h)) {
            return Err(Denied::Host);
        }
        if let Some(origin) = claims.origin {
            let authority = origin.strip_prefix("http://");
            if !authority.is_some_and(|a| self.is_own_authority(a)) {
                return Err(Denied::Origin);
            }
        }
        match claims.token {
            Some(t) if same_secret(t.as_bytes(), self.token.as_bytes()) => Ok(()),
            _ => Err(Denied::Token),
        }
    }

    /// `127.0.0.1:PORT` or `localhost:PORT` (a browser always sends the port of a
    /// non-default one).
    fn is_own_authority(&self, authority: &str) -> bool {
        let Some((host, port)) = authority.rsplit_once(':') else { return false };
        let own_host = host == "127.0.0.1" || host.eq_ignore_ascii_case("localhost");
        own_host && port.parse::<u16>().is_ok_and(|p| p == self.port)
    }
}

/// Compares in time independent of where the texts first differ.
fn same_secret(given: &[u8], secret: &[u8]) -> bool {
    if given.len() != secret.len() {
        return false;
    }
    given.iter().zip(secret).fold(0u8, |acc, (a, b)| acc | (a ^ b)) == 0
}

/// 128 random bits as 32 hex digits. std's `RandomState` is keyed from the operating
/// system's random source (getrandom) once per thread; SipHash under that secret key is a
/// pseudo-random function, so its outputs cannot be guessed without the key. No crate needed.
pub fn random_token() -> String {
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    (0..2u64)
        .map(|i| {
            let mut hasher = std::collections::hash_map::RandomState::new().build_hasher();
            hasher.write_u64(i);
            hasher.write_u128(now);
            format!("{:016x}", hasher.finish())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn guard() -> Guard {
        Guard::new(8123, "abc".repeat(10))
    }

    fn claims<'a>(host: Option<&'a str>, origin: Option<&'a str>, token: Option<&'a str>) -> Claims<'a> {
        Claims { host, origin, token }
    }

    #[test]
    fn only_this_server_with_the_token_is_admitted() {
        let g = guard();
        let t = "abc".repeat(10);
        assert_eq!(g.admit(&claims(Some("127.0.0.1:8123"), None, Some(&t))), Ok(()));
        assert_eq!(g.admit(&claims(Some("localhost:8123"), Some("http://localhost:8123"), Some(&t))), Ok(()));
        assert_eq!(g.admit(&claims(Some("evil.example:8123"), None, Some(&t))), Err(Denied::Host));
        assert_eq!(g.admit(&claims(Some("127.0.0.1:8124"), None, Some(&t))), Err(Denied::Host));
        assert_eq!(g.admit(&claims(None, None, Some(&t))), Err(Denied::Host));
        assert_eq!(
            g.admit(&claims(Some("127.0.0.1:8123"), Some("http://evil.example"), Some(&t))),
            Err(Denied::Origin)
        );
        assert_eq!(g.admit(&claims(Some("127.0.0.1:8123"), Some("null"), Some(&t))), Err(Denied::Origin));
        assert_eq!(g.admit(&claims(Some("127.0.0.1:8123"), None, None)), Err(Denied::Token));
        assert_eq!(g.admit(&claims(Some("127.0.0.1:8123"), None, Some("abc"))), Err(Denied::Token));
    }

    #[test]
    fn tokens_are_long_and_differ() {
        let (a, b) = (random_token(), random_token());
        assert_eq!(a.len(), 32);
        assert!(a.chars().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a, b);
    }
}
