//! Which `Host` and `Origin` headers the server answers to.
//!
//! A page on another site can have its name re-pointed at 127.0.0.1 (DNS rebinding) and then
//! reach the viewer as if it were the viewer's own page, with a `Host` and an `Origin` that
//! name that site. The server therefore answers only to requests whose `Host` is this machine:
//! a loopback name (`localhost`, `*.localhost`, `127.0.0.0/8`, `[::1]`) or the exact address it
//! is bound to, with the port it listens on, or a name given on purpose
//! ([`HostPolicy::allow`]); an `Origin`, when sent, must name such a host as well, or be an
//! origin allowed on purpose ([`HostPolicy::allow_origin`], e.g. the Foxglove web app's), and
//! `Origin: null` (a sandboxed or local page) is refused.

use std::net::{IpAddr, SocketAddr};

/// The hosts a server answers to.
#[derive(Debug, Clone)]
pub struct HostPolicy {
    bound: SocketAddr,
    allowed: Vec<Allowed>,
    origins: Vec<String>,
}

/// A name allowed on purpose: with a port, only that port; without, any port.
#[derive(Debug, Clone)]
struct Allowed {
    host: String,
    port: Option<u16>,
}

impl HostPolicy {
    /// Loopback names and `bound` itself, on `bound`'s port.
    pub fn new(bound: SocketAddr) -> Self {
        Self {
            bound,
            allowed: Vec::new(),
            origins: Vec::new(),
        }
    }

    /// Also answers requests sent from pages of `origin` (`https://app.foxglove.dev`, compared
    /// exactly, case aside), their `Host` still checked: a client application served from
    /// elsewhere that connects to this machine on purpose.
    pub fn allow_origin(mut self, origin: &str) -> Self {
        self.origins
            .push(origin.trim_end_matches('/').to_ascii_lowercase());
        self
    }

    /// Also answers to `name` (`viewer.example` on any port, `viewer.example:8443` on that
    /// one; an IPv6 address in brackets), for a server reached by that name on purpose.
    ///
    /// # Errors
    ///
    /// [`BadHostName`] when `name` is not a host name or address with an optional port.
    pub fn allow(mut self, name: &str) -> Result<Self, BadHostName> {
        let (host, port) = split_host(name).ok_or_else(|| BadHostName(name.to_owned()))?;
        if host.is_empty() || host.chars().any(|c| c.is_whitespace() || c == '/') {
            return Err(BadHostName(name.to_owned()));
        }
        self.allowed.push(Allowed {
            host: host.to_ascii_lowercase(),
            port,
        });
        Ok(self)
    }

    /// True if a request carrying these headers may be answered.
    pub fn permits(&self, host: Option<&[u8]>, origin: Option<&[u8]>) -> bool {
        let Some(host) = host.and_then(|h| std::str::from_utf8(h).ok()) else {
            return false;
        };
        if !self.host_ok(host, None) {
            return false;
        }
        match origin {
            None => true,
            Some(o) => std::str::from_utf8(o).is_ok_and(|o| {
                let exact = o.trim_end_matches('/').to_ascii_lowercase();
                self.origins.contains(&exact) || self.origin_ok(o)
            }),
        }
    }

    /// `host[:port]`; `default_port` is the port a missing one stands for.
    fn host_ok(&self, authority: &str, default_port: Option<u16>) -> bool {
        let Some((name, port)) = split_host(authority) else {
            return false;
        };
        let name = name.to_ascii_lowercase();
        let port = port.or(default_port).unwrap_or(80);
        if self
            .allowed
            .iter()
            .any(|a| a.host == name && a.port.is_none_or(|p| p == port))
        {
            return true;
        }
        if port != self.bound.port() {
            return false;
        }
        if name == "localhost" || name.ends_with(".localhost") {
            return true;
        }
        let ip = name
            .strip_prefix('[')
            .and_then(|n| n.strip_suffix(']'))
            .unwrap_or(&name)
            .parse::<IpAddr>();
        match ip {
            Ok(IpAddr::V4(v4)) => v4.is_loopback() || IpAddr::V4(v4) == self.bound.ip(),
            Ok(IpAddr::V6(v6)) => v6.is_loopback() || IpAddr::V6(v6) == self.bound.ip(),
            Err(_) => false,
        }
    }

    /// `scheme://host[:port]`, the scheme http or https (`null` and anything else refused).
    fn origin_ok(&self, origin: &str) -> bool {
        let Some((scheme, rest)) = origin.split_once("://") else {
            return false;
        };
        let default_port = match scheme.to_ascii_lowercase().as_str() {
            "http" => 80,
            "https" => 443,
            _ => return false,
        };
        let authority = rest.strip_suffix('/').unwrap_or(rest);
        !authority.contains(['/', '@', '?', '#']) && self.host_ok(authority, Some(default_port))
    }
}

/// A name given to [`HostPolicy::allow`] that is not a host.
#[derive(Debug, thiserror::Error)]
#[error("{0:?}: expected a host name or address, with an optional port (viewer.example:8080)")]
pub struct BadHostName(pub String);

/// `name[:port]` or `[v6][:port]` split; `None` if the port is not a number.
fn split_host(authority: &str) -> Option<(&str, Option<u16>)> {
    if authority.starts_with('[') {
        let end = authority.find(']')?;
        let (name, rest) = authority.split_at(end + 1);
        return match rest {
            "" => Some((name, None)),
            _ => Some((name, Some(rest.strip_prefix(':')?.parse().ok()?))),
        };
    }
    match authority.rsplit_once(':') {
        None => Some((authority, None)),
        Some((name, port)) if !name.contains(':') => Some((name, Some(port.parse().ok()?))),
        // A bare IPv6 address is not a valid Host.
        Some(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn policy() -> HostPolicy {
        HostPolicy::new("127.0.0.1:8080".parse().expect("address"))
    }

    fn ok(p: &HostPolicy, host: &str, origin: Option<&str>) -> bool {
        p.permits(Some(host.as_bytes()), origin.map(str::as_bytes))
    }

    #[test]
    fn loopback_names_on_the_bound_port_are_answered() {
        let p = policy();
        for host in [
            "127.0.0.1:8080",
            "127.1.2.3:8080",
            "localhost:8080",
            "LocalHost:8080",
            "viewer.localhost:8080",
            "[::1]:8080",
        ] {
            assert!(ok(&p, host, None), "{host}");
            assert!(ok(&p, host, Some(&format!("http://{host}"))), "{host}");
        }
    }

    #[test]
    fn other_hosts_other_ports_and_odd_origins_are_refused() {
        let p = policy();
        assert!(!p.permits(None, None));
        assert!(!p.permits(Some(b"\xff"), None));
        for host in [
            "evil.example:8080",
            "evil.example",
            "localhost.evil.example:8080",
            "127.0.0.1:9999",
            "127.0.0.1",
            "10.0.0.1:8080",
            "::1:8080",
            "[::1]:x",
            "",
        ] {
            assert!(!ok(&p, host, None), "{host}");
        }
        let host = "127.0.0.1:8080";
        for origin in [
            "null",
            "http://evil.example:8080",
            "http://evil.example",
            "http://127.0.0.1:9999",
            "http://127.0.0.1",
            "file://",
            "ftp://127.0.0.1:8080",
            "http://evil.example@127.0.0.1:8080",
            "127.0.0.1:8080",
        ] {
            assert!(!ok(&p, host, Some(origin)), "{origin}");
        }
        // The rebinding request: a matching Host and Origin naming another site.
        assert!(!ok(
            &p,
            "evil.example:8080",
            Some("http://evil.example:8080")
        ));
    }

    #[test]
    fn the_bound_address_and_allowed_names_are_answered() {
        let p = HostPolicy::new("192.168.1.5:8080".parse().expect("address"));
        assert!(ok(&p, "192.168.1.5:8080", Some("http://192.168.1.5:8080")));
        assert!(!ok(&p, "192.168.1.6:8080", None));
        let p = policy()
            .allow("viewer.example")
            .expect("name")
            .allow("other.example:9000")
            .expect("name with port");
        assert!(ok(&p, "viewer.example", Some("https://viewer.example")));
        assert!(ok(&p, "VIEWER.example:8080", None));
        assert!(ok(
            &p,
            "other.example:9000",
            Some("http://other.example:9000")
        ));
        assert!(!ok(&p, "other.example:8080", None));
        assert!(!ok(&p, "evil.example:8080", None));
        let p = policy().allow_origin("https://App.Foxglove.dev");
        assert!(ok(&p, "localhost:8080", Some("https://app.foxglove.dev")));
        assert!(ok(&p, "localhost:8080", Some("https://app.foxglove.dev/")));
        assert!(!ok(
            &p,
            "evil.example:8080",
            Some("https://app.foxglove.dev")
        ));
        assert!(!ok(
            &p,
            "localhost:8080",
            Some("https://app.foxglove.dev.evil.example")
        ));
        assert!(!ok(&p, "localhost:8080", Some("null")));
        for bad in ["", "a b", "x:port", "a/b", "[::1"] {
            assert!(policy().allow(bad).is_err(), "{bad}");
        }
    }
}
