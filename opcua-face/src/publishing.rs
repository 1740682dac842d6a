//! The door's one look inside a message: the publishing interval a client
//! asks for.
//!
//! The OPC UA library revises a subscription's publishing interval only up
//! to a minimum: an interval of `inf` or 1e12 ms was kept as asked,
//! and a subscription that never publishes holds its place for ever.
//! On a channel without security (`SecurityPolicy#None`: the anonymous
//! clients on loopback) the door reads `CreateSubscription` and
//! `ModifySubscription` requests and lowers an interval above
//! [`MAX_PUBLISHING_INTERVAL_MS`] (or one that is not a number) to it, in
//! place, before the library sees it; the library then answers the bound
//! as the revised interval. Signed or encrypted channels (remote clients,
//! who must present the access token) are not touched: their bytes cannot
//! change.
//!
//! The layout is OPC UA's binary encoding (Part 6): a chunk header, the
//! secure channel, token, sequence and request ids, the body's type
//! NodeId, the RequestHeader, then the request's fields.

/// The longest publishing interval a client on a plain channel gets, in ms.
pub const MAX_PUBLISHING_INTERVAL_MS: f64 = 600_000.0;

/// The security policy of a channel without security.
const POLICY_NONE: &[u8] = b"http://opcfoundation.org/UA/SecurityPolicy#None";

/// Binary encoding ids of the two requests (namespace 0).
const CREATE_SUBSCRIPTION: u32 = 787;
const MODIFY_SUBSCRIPTION: u32 = 793;

/// Where a MSG chunk's body starts: header 8, channel id, token id,
/// sequence number and request id 4 each.
const MSG_BODY: usize = 24;

/// Where an OPN chunk's security policy URI starts: header 8, channel id 4.
const OPN_POLICY: usize = 12;

/// What the door knows of one connection's secure channel.
#[derive(Debug, Default)]
pub(crate) struct Channel {
    /// The channel was opened without security.
    plain: bool,
}

impl Channel {
    /// Looks at one whole chunk from the client (header included) and
    /// bounds the publishing interval it asks for, where it may.
    pub(crate) fn look(&mut self, chunk: &mut [u8]) {
        match chunk.get(..4) {
            Some(b"OPNF") => {
                self.plain = Reader::at(chunk, OPN_POLICY).bytes() == Some(POLICY_NONE);
            }
            Some(b"MSGF") if self.plain => bound_interval(chunk),
            _ => {}
        }
    }
}

/// Lowers the publishing interval of a CreateSubscription or
/// ModifySubscription request in `chunk` to the bound.
fn bound_interval(chunk: &mut [u8]) {
    let Some(at) = interval_at(chunk) else {
        return;
    };
    let Some(field) = chunk.get_mut(at..at + 8) else {
        return;
    };
    let mut bytes = [0u8; 8];
    bytes.copy_from_slice(field);
    let asked = f64::from_le_bytes(bytes);
    if asked.is_nan() || asked > MAX_PUBLISHING_INTERVAL_MS {
        field.copy_from_slice(&MAX_PUBLISHING_INTERVAL_MS.to_le_bytes());
    }
}

/// Where the requested publishing interval of the request in `chunk`
/// starts, if it is one of the two.
fn interval_at(chunk: &[u8]) -> Option<usize> {
    let mut r = Reader::at(chunk, MSG_BODY);
    let (ns, id) = r.node_id()?;
    if ns != 0 {
        return None;
    }
    match id {
        Some(CREATE_SUBSCRIPTION) => {
            r.request_header()?;
        }
        Some(MODIFY_SUBSCRIPTION) => {
            r.request_header()?;
            r.skip(4)?; // SubscriptionId
        }
        _ => return None,
    }
    Some(r.at)
}

/// Reads OPC UA binary values; every read checks its bounds.
struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn at(b: &'a [u8], at: usize) -> Self {
        Reader { b, at }
    }

    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let end = self.at.checked_add(n)?;
        let s = self.b.get(self.at..end)?;
        self.at = end;
        Some(s)
    }

    fn skip(&mut self, n: usize) -> Option<()> {
        self.take(n).map(|_| ())
    }

    fn u8(&mut self) -> Option<u8> {
        self.take(1).map(|s| s[0])
    }

    fn u16(&mut self) -> Option<u16> {
        self.take(2).map(|s| u16::from_le_bytes([s[0], s[1]]))
    }

    fn u32(&mut self) -> Option<u32> {
        self.take(4)
            .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    }

    /// A String or ByteString: `None` when malformed, `Some(&[])` for null.
    fn bytes(&mut self) -> Option<&'a [u8]> {
        let len = self.u32()? as i32;
        if len < 0 {
            return Some(&[]);
        }
        self.take(usize::try_from(len).ok()?)
    }

    /// A NodeId: its namespace and, if numeric, its id.
    fn node_id(&mut self) -> Option<(u16, Option<u32>)> {
        match self.u8()? {
            0 => Some((0, Some(u32::from(self.u8()?)))),
            1 => {
                let ns = u16::from(self.u8()?);
                Some((ns, Some(u32::from(self.u16()?))))
            }
            2 => Some((self.u16()?, Some(self.u32()?))),
            3 | 5 => {
                let ns = self.u16()?;
                self.bytes()?;
                Some((ns, None))
            }
            4 => {
                let ns = self.u16()?;
                self.skip(16)?;
                Some((ns, None))
            }
            _ => None,
        }
    }

    /// An ExtensionObject: its type NodeId and its body, if any.
    fn extension_object(&mut self) -> Option<()> {
        self.node_id()?;
        match self.u8()? {
            0 => Some(()),
            1 | 2 => self.bytes().map(|_| ()),
            _ => None,
        }
    }

    /// The RequestHeader: authentication token, timestamp, request handle,
    /// return diagnostics, audit entry id, timeout hint, additional header.
    fn request_header(&mut self) -> Option<()> {
        self.node_id()?;
        self.skip(8 + 4 + 4)?;
        self.bytes()?;
        self.skip(4)?;
        self.extension_object()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    fn chunk(kind: &[u8; 4], body: &[u8]) -> Vec<u8> {
        let mut c = kind.to_vec();
        c.extend(u32::try_from(8 + body.len()).unwrap().to_le_bytes());
        c.extend(body);
        c
    }

    fn opn(policy: &[u8]) -> Vec<u8> {
        let mut body = 0u32.to_le_bytes().to_vec();
        body.extend(u32::try_from(policy.len()).unwrap().to_le_bytes());
        body.extend(policy);
        body.extend((-1i32).to_le_bytes()); // sender certificate
        chunk(b"OPNF", &body)
    }

    /// A request of type `id` with a RequestHeader as a real client sends
    /// it (a ByteString token, an audit id, no additional header), then
    /// `fields`; the interval's offset in the chunk.
    fn msg(id: u16, fields: &[u8], interval: f64) -> (Vec<u8>, usize) {
        let mut body = vec![0u8; 16]; // channel, token, sequence, request ids
        body.push(1);
        body.push(0);
        body.extend(id.to_le_bytes());
        body.push(5); // ByteString NodeId
        body.extend(0u16.to_le_bytes());
        body.extend(32u32.to_le_bytes());
        body.extend([7u8; 32]);
        body.extend([0u8; 16]); // timestamp, handle, diagnostics
        body.extend(3u32.to_le_bytes());
        body.extend(b"abc");
        body.extend(0u32.to_le_bytes()); // timeout hint
        body.extend([0u8, 0, 0]); // additional header: null NodeId, no body
        body.extend(fields);
        let at = 8 + body.len();
        body.extend(interval.to_le_bytes());
        body.extend([0u8; 13]); // the rest of the request
        (chunk(b"MSGF", &body), at)
    }

    fn interval(c: &[u8], at: usize) -> f64 {
        f64::from_le_bytes(c[at..at + 8].try_into().unwrap())
    }

    #[test]
    fn an_endless_interval_on_a_plain_channel_is_bounded() {
        let mut ch = Channel::default();
        ch.look(&mut opn(POLICY_NONE));
        for asked in [f64::INFINITY, 1e12, f64::NAN, 600_001.0] {
            let (mut c, at) = msg(787, &[], asked);
            ch.look(&mut c);
            assert_eq!(interval(&c, at), MAX_PUBLISHING_INTERVAL_MS, "{asked}");
            let (mut c, at) = msg(793, &9u32.to_le_bytes(), asked);
            ch.look(&mut c);
            assert_eq!(interval(&c, at), MAX_PUBLISHING_INTERVAL_MS, "{asked}");
        }
    }

    #[test]
    fn a_bounded_interval_and_other_requests_are_left_as_they_are() {
        let mut ch = Channel::default();
        ch.look(&mut opn(POLICY_NONE));
        let (mut c, at) = msg(787, &[], 250.0);
        let before = c.clone();
        ch.look(&mut c);
        assert_eq!((c == before, interval(&c, at)), (true, 250.0));
        let (mut c, _) = msg(631, &[], f64::INFINITY); // a Read
        let before = c.clone();
        ch.look(&mut c);
        assert_eq!(c, before);
    }

    #[test]
    fn a_secured_channel_is_never_touched() {
        let mut ch = Channel::default();
        ch.look(&mut opn(
            b"http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256",
        ));
        let (mut c, _) = msg(787, &[], f64::INFINITY);
        let before = c.clone();
        ch.look(&mut c);
        assert_eq!(c, before);
    }

    #[test]
    fn a_cut_or_garbled_request_is_passed_on_unchanged() {
        let mut ch = Channel::default();
        ch.look(&mut opn(POLICY_NONE));
        let (c, at) = msg(787, &[], f64::INFINITY);
        for end in [10, 30, at, at + 4] {
            let mut cut = c[..end].to_vec();
            let before = cut.clone();
            ch.look(&mut cut);
            assert_eq!(cut, before, "cut at {end}");
        }
        let mut bad = c.clone();
        bad[MSG_BODY + 4] = 9; // an unknown NodeId encoding in the header
        let before = bad.clone();
        ch.look(&mut bad);
        assert_eq!(bad, before);
    }
}
