//! The language server's transport over stdio: `Content-Length` framing read with bounds.
//!
//! `lsp-server`'s own reader ends the server on a malformed message and allocates whatever a
//! `Content-Length` says; this one reads a header line of at most [`MAX_HEADER_LINE`] bytes,
//! refuses a body over [`MAX_MESSAGE_BYTES`] (the body is read and dropped, never kept), and
//! answers or logs a body that is not a JSON-RPC message and goes on with the next one. A
//! request that cannot be read but has an id is answered with `InvalidRequest`; anything else
//! is logged on stderr.

use crossbeam_channel::{Receiver, Sender};
use lsp_server::{Connection, ErrorCode, Message, RequestId, Response};
use std::io::{BufRead, Read as _};

/// The largest message body the server reads, bytes. A document of the largest input holoc
/// reads (32 MiB) with JSON escapes fits.
pub const MAX_MESSAGE_BYTES: usize = 64 * 1024 * 1024;

/// The longest header line, bytes.
pub const MAX_HEADER_LINE: usize = 8 * 1024;

/// What one frame of the input holds.
#[derive(Debug)]
pub enum Frame {
    /// A message.
    Message(Message),
    /// A frame that is not a message, with why, and the id of the request when one is readable.
    Bad(String, Option<RequestId>),
    /// A body that is not JSON: answered with JSON-RPC's parse error (`id: null`).
    NotJson(String),
}

/// The JSON-RPC answer to a body that is not JSON: a parse error whose id is `null`.
pub fn parse_error(why: &str) -> String {
    serde_json::json!({
        "jsonrpc": "2.0",
        "id": null,
        "error": {"code": ErrorCode::ParseError as i32, "message": why},
    })
    .to_string()
}

/// Reads the next frame, or `None` at the end of the input.
///
/// # Errors
/// An I/O error of the input, or an input that ends inside a frame.
pub fn read_frame(input: &mut impl BufRead) -> std::io::Result<Option<Frame>> {
    let mut size: Option<Result<usize, String>> = None;
    let mut line = Vec::new();
    let mut any = false;
    loop {
        line.clear();
        let n = input.by_ref().take(MAX_HEADER_LINE as u64 + 1).read_until(b'\n', &mut line)?;
        if n == 0 {
            return if any {
                Err(std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    "the input ends in a header",
                ))
            } else {
                Ok(None)
            };
        }
        any = true;
        if line.len() > MAX_HEADER_LINE {
            // Skip the rest of the line.
            let mut rest = Vec::new();
            input.read_until(b'\n', &mut rest)?;
            size = Some(Err(format!("a header line is longer than {MAX_HEADER_LINE} bytes")));
            continue;
        }
        let text = String::from_utf8_lossy(&line);
        let text = text.trim_end_matches(['\r', '\n']);
        if text.is_empty() {
            break;
        }
        if let Some((name, value)) = text.split_once(':') {
            if name.trim().eq_ignore_ascii_case("Content-Length") {
                size = Some(
                    value
                        .trim()
                        .parse::<u64>()
                        .map_err(|_| format!("`Content-Length: {}` is not a length", value.trim()))
                        .and_then(|n| {
                            usize::try_from(n).ok().filter(|&n| n <= MAX_MESSAGE_BYTES).ok_or(
                                format!(
                        "a message of {n} bytes is over the limit of {MAX_MESSAGE_BYTES} bytes"
                    ),
                            )
                        }),
                );
            }
        }
    }
    let size = match size {
        Some(Ok(size)) => size,
        Some(Err(why)) => {
            // The body of a refused length is read and dropped when its length is known.
            if let Some(n) = why.strip_prefix("a message of ").and_then(|r| r.split(' ').next()) {
                if let Ok(n) = n.parse::<u64>() {
                    std::io::copy(&mut input.by_ref().take(n), &mut std::io::sink())?;
                }
            }
            return Ok(Some(Frame::Bad(why, None)));
        }
        None => return Ok(Some(Frame::Bad("a message without `Content-Length`".into(), None))),
    };
    let mut body = vec![0; size];
    input.read_exact(&mut body)?;
    Ok(Some(decode(&body)))
}

/// A body as a message, or why it is not one.
fn decode(body: &[u8]) -> Frame {
    let value = match serde_json::from_slice::<serde_json::Value>(body) {
        Ok(value) => value,
        Err(e) => return Frame::NotJson(format!("a message that is not JSON: {e}")),
    };
    let id = value.get("id").and_then(|id| serde_json::from_value::<RequestId>(id.clone()).ok());
    // A request whose method is not a string would read as a response and be dropped unseen.
    if value.get("method").is_some_and(|m| !m.is_string()) {
        return Frame::Bad("a message that is not JSON-RPC: its method is not a string".into(), id);
    }
    match serde_json::from_value::<Message>(value) {
        Ok(message) => Frame::Message(message),
        Err(e) => Frame::Bad(format!("a message that is not JSON-RPC: {e}"), id),
    }
}

/// The threads of a stdio connection.
pub struct Threads {
    reader: std::thread::JoinHandle<()>,
    writer: std::thread::JoinHandle<std::io::Result<()>>,
}

impl Threads {
    /// Waits for the writer to send everything; the reader is waited for only when it has
    /// ended (it ends after `exit` or at the end of the input).
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn join(self) -> Result<(), String> {
        let written = self.writer.join().map_err(|_| "the writer thread panicked".to_string())?;
        if self.reader.is_finished() {
            let _ = self.reader.join();
        }
        written.map_err(|e| e.to_string())
    }
}

/// A connection on stdin and stdout with the bounded reader.
#[allow(clippy::print_stderr, reason = "stdout is the protocol's; the transport logs on stderr")]
pub fn stdio() -> (Connection, Threads) {
    let (to_server, from_client): (Sender<Message>, Receiver<Message>) =
        crossbeam_channel::bounded(0);
    let (to_client, outgoing): (Sender<Message>, Receiver<Message>) = crossbeam_channel::bounded(0);
    let answers = to_client.clone();
    // Answers `lsp-server`'s messages cannot say (an id that is `null`), already in JSON.
    let (raw_answers, raw): (Sender<String>, Receiver<String>) = crossbeam_channel::unbounded();
    let writer = std::thread::spawn(move || {
        use std::io::Write as _;
        let stdout = std::io::stdout();
        let mut stdout = stdout.lock();
        let mut raw = raw;
        loop {
            crossbeam_channel::select! {
                recv(outgoing) -> message => match message {
                    Ok(message) => message.write(&mut stdout)?,
                    Err(_) => return Ok(()),
                },
                recv(raw) -> body => match body {
                    Ok(body) => {
                        write!(stdout, "Content-Length: {}\r\n\r\n{body}", body.len())?;
                        stdout.flush()?;
                    }
                    // The reader is gone; the messages go on until the server's end closes.
                    Err(_) => raw = crossbeam_channel::never(),
                },
            }
        }
    });
    let reader = std::thread::spawn(move || {
        let stdin = std::io::stdin();
        let mut stdin = stdin.lock();
        loop {
            match read_frame(&mut stdin) {
                Ok(Some(Frame::Message(message))) => {
                    let exit = matches!(&message, Message::Notification(n) if n.method == "exit");
                    if to_server.send(message).is_err() || exit {
                        return;
                    }
                }
                Ok(Some(Frame::NotJson(why))) => {
                    eprintln!("holoc lsp: answered a parse error: {why}");
                    let _ = raw_answers.send(parse_error(&why));
                }
                Ok(Some(Frame::Bad(why, id))) => {
                    eprintln!("holoc lsp: skipped {why}");
                    if let Some(id) = id {
                        let response = Response::new_err(id, ErrorCode::InvalidRequest as i32, why);
                        let _ = answers.send(Message::Response(response));
                    }
                }
                Ok(None) => return,
                Err(e) => {
                    eprintln!("holoc lsp: the input ended: {e}");
                    return;
                }
            }
        }
    });
    (Connection { sender: to_client, receiver: from_client }, Threads { reader, writer })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(input: &[u8]) -> Vec<String> {
        let mut reader = std::io::BufReader::new(input);
        let mut out = Vec::new();
        while let Ok(Some(frame)) = read_frame(&mut reader) {
            out.push(match frame {
                Frame::Message(m) => {
                    format!("message {}", serde_json::to_string(&m).unwrap_or_default())
                }
                Frame::Bad(why, id) => format!("bad {why} {id:?}"),
                Frame::NotJson(why) => format!("parse error {why}"),
            });
        }
        out
    }

    fn framed(body: &str) -> String {
        format!("Content-Length: {}\r\n\r\n{body}", body.len())
    }

    #[test]
    fn bad_frames_are_skipped_and_reading_goes_on() {
        let good = framed(r#"{"jsonrpc":"2.0","method":"initialized","params":{}}"#);
        let input = format!(
            "{}{}{}{}{}Content-Length: 99999999999\r\n\r\n{}",
            framed("{not json"),
            framed(r#"{"jsonrpc":"2.0","id":7,"method":5}"#),
            "X-Other: 1\r\n\r\n",
            framed("[]"),
            good,
            "short"
        );
        let got = frames(input.as_bytes());
        assert_eq!(got.len(), 6, "{got:#?}");
        assert!(got[0].starts_with("parse error a message that is not JSON"), "{got:#?}");
        assert!(got[1].contains("Some(RequestId(I32(7)))"), "{got:#?}");
        assert!(got[2].starts_with("bad a message without `Content-Length`"), "{got:#?}");
        assert!(got[3].ends_with("None"), "{got:#?}");
        assert!(got[4].starts_with("message "), "{got:#?}");
        // A length over the limit is refused without allocating it; its body is skipped.
        assert!(got[5].contains("over the limit"), "{got:#?}");
    }
}
