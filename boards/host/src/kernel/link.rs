//! The byte stream of one encapsulation session: the TCP connection itself (port 44818), or
//! TLS over it (port 2221, feature `tls`), read and written alike by [`super::session`].

use std::io::{self, Read, Write};
use std::net::{Shutdown, TcpStream};

/// One session's connection.
pub enum Link {
    /// Plaintext, on 44818.
    Plain(TcpStream),
    /// TLS, on 2221.
    #[cfg(feature = "tls")]
    Tls(Box<openssl::ssl::SslStream<TcpStream>>),
}

/// Where a TLS handshake is.
#[cfg_attr(not(feature = "tls"), allow(dead_code))]
pub enum Handshake {
    /// Complete (always, for plaintext).
    Done,
    /// Waits until the socket is readable (`false`) or writable (`true`).
    Waiting(bool),
    /// Failed, for this reason.
    Failed(String),
}

impl Link {
    /// The TCP connection under it.
    pub fn tcp(&self) -> &TcpStream {
        match self {
            Link::Plain(s) => s,
            #[cfg(feature = "tls")]
            Link::Tls(s) => s.get_ref(),
        }
    }

    /// Reads plaintext (WouldBlock until some is there; 0 at the peer's close).
    pub fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self {
            Link::Plain(s) => s.read(buf),
            #[cfg(feature = "tls")]
            Link::Tls(s) => s.read(buf),
        }
    }

    /// Writes plaintext (WouldBlock while the kernel has no room).
    pub fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self {
            Link::Plain(s) => s.write(buf),
            #[cfg(feature = "tls")]
            Link::Tls(s) => s.write(buf),
        }
    }

    /// Ends our side: TLS close_notify (if it can go at once), then our FIN.
    pub fn shutdown(&mut self) {
        #[cfg(feature = "tls")]
        if let Link::Tls(s) = self {
            let _ = s.shutdown();
        }
        let _ = self.tcp().shutdown(Shutdown::Write);
    }

    /// Moves the TLS handshake on as far as the socket allows.
    pub fn handshake(&mut self) -> Handshake {
        match self {
            Link::Plain(_) => Handshake::Done,
            #[cfg(feature = "tls")]
            Link::Tls(s) => match s.accept() {
                Ok(()) => Handshake::Done,
                Err(e) => match e.code() {
                    openssl::ssl::ErrorCode::WANT_READ => Handshake::Waiting(false),
                    openssl::ssl::ErrorCode::WANT_WRITE => Handshake::Waiting(true),
                    _ => {
                        let why = e
                            .ssl_error()
                            .map_or_else(|| e.to_string(), |stack| stack.to_string());
                        // The reason a peer's certificate was refused (expired, unknown CA).
                        let verify = s.ssl().verify_result();
                        Handshake::Failed(match verify == openssl::x509::X509VerifyResult::OK {
                            true => why,
                            false => format!("{why} ({})", verify.error_string()),
                        })
                    }
                },
            },
        }
    }

    /// The protocol version and cipher suite, once a TLS handshake completed.
    pub fn describe(&self) -> Option<String> {
        match self {
            Link::Plain(_) => None,
            #[cfg(feature = "tls")]
            Link::Tls(s) => {
                let ssl = s.ssl();
                let cipher = ssl.current_cipher().map_or("?", |c| c.name());
                Some(format!("{} {cipher}", ssl.version_str()))
            }
        }
    }
}
