//! The serialized FMU state: a fixed little-endian header followed by a postcard payload.
//!
//! ```text
//! offset size field
//!      0    8 magic, chosen by the layer (FMI 2.0: "FMI2SNAP")
//!      8    2 format version (this layout) = 1
//!     10    2 reserved, 0
//!     12    4 Model::STATE_VERSION
//!     16   16 interface GUID of the model (binary UUID): a foreign FMU's buffer is refused
//!     32    8 payload length in bytes
//!     40    4 CRC-32 (IEEE) of the payload
//!     44    n payload: postcard encoding of the layer's state (f64 as raw bits: exact)
//! ```
//! Every field is checked before the payload is decoded, and the buffer length must equal
//! header + payload exactly; reads go through bounds-checked slices only.
use serde::{de::DeserializeOwned, Serialize};
use uuid::Uuid;

const FORMAT_VERSION: u16 = 1;
pub const HEADER_LEN: usize = 44;

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SnapshotError {
    #[error("buffer of {len} bytes is shorter than the {HEADER_LEN}-byte header")]
    TooShort { len: usize },
    #[error("buffer does not start with the FMU-state magic bytes")]
    BadMagic,
    #[error("format version {found}, this FMU reads version {FORMAT_VERSION}")]
    FormatVersion { found: u16 },
    #[error("model state version {found}, this FMU has version {expected}")]
    StateVersion { found: u32, expected: u32 },
    #[error("state of a different FMU (GUID {{{found}}}, this FMU is {{{expected}}})")]
    ForeignGuid { found: Uuid, expected: Uuid },
    #[error("buffer of {len} bytes, header announces {expected}")]
    LengthMismatch { len: usize, expected: u64 },
    #[error("payload checksum mismatch (corrupted buffer)")]
    Checksum,
    #[error("payload cannot be decoded: {0}")]
    Payload(String),
    #[error("payload cannot be encoded: {0}")]
    Encode(String),
}

/// What identifies a buffer as ours: the layer's magic bytes, the model's state version and
/// the interface GUID.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    pub magic: [u8; 8],
    pub state_version: u32,
    pub guid: Uuid,
}

pub fn encode<T: Serialize>(state: &T, header: Header) -> Result<Vec<u8>, SnapshotError> {
    let Header {
        magic,
        state_version,
        guid,
    } = header;
    let payload = postcard::to_allocvec(state).map_err(|e| SnapshotError::Encode(e.to_string()))?;
    let mut bytes = Vec::with_capacity(HEADER_LEN + payload.len());
    bytes.extend_from_slice(&magic);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&0u16.to_le_bytes());
    bytes.extend_from_slice(&state_version.to_le_bytes());
    bytes.extend_from_slice(guid.as_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    debug_assert_eq!(bytes.len(), HEADER_LEN);
    bytes.extend_from_slice(&payload);
    Ok(bytes)
}

/// `sealed`'s header (its first [`HEADER_LEN`] bytes) around another `payload`, with the
/// length and checksum recomputed: a buffer that passes every integrity check whatever it
/// holds. For tests and fuzzers that craft states; an FMU never needs it.
pub fn reseal(sealed: &[u8], payload: &[u8]) -> Vec<u8> {
    let mut bytes = sealed[..HEADER_LEN - 12].to_vec();
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(payload).to_le_bytes());
    bytes.extend_from_slice(payload);
    bytes
}

pub fn decode<T: DeserializeOwned>(bytes: &[u8], header: Header) -> Result<T, SnapshotError> {
    let Header {
        magic,
        state_version: expected_version,
        guid,
    } = header;
    let header = bytes
        .get(..HEADER_LEN)
        .ok_or(SnapshotError::TooShort { len: bytes.len() })?;
    let field = |at: usize, n: usize| &header[at..at + n];
    if field(0, 8) != magic {
        return Err(SnapshotError::BadMagic);
    }
    let format = u16::from_le_bytes(field(8, 2).try_into().expect("2 bytes"));
    if format != FORMAT_VERSION {
        return Err(SnapshotError::FormatVersion { found: format });
    }
    // Which FMU first: a state of another FMU is that, whatever its version.
    let found = Uuid::from_slice(field(16, 16)).expect("16 bytes");
    if found != guid {
        return Err(SnapshotError::ForeignGuid {
            found,
            expected: guid,
        });
    }
    let state_version = u32::from_le_bytes(field(12, 4).try_into().expect("4 bytes"));
    if state_version != expected_version {
        return Err(SnapshotError::StateVersion {
            found: state_version,
            expected: expected_version,
        });
    }
    let payload_len = u64::from_le_bytes(field(32, 8).try_into().expect("8 bytes"));
    let expected = (HEADER_LEN as u64).saturating_add(payload_len);
    if bytes.len() as u64 != expected {
        return Err(SnapshotError::LengthMismatch {
            len: bytes.len(),
            expected,
        });
    }
    let crc = u32::from_le_bytes(field(40, 4).try_into().expect("4 bytes"));
    let payload = &bytes[HEADER_LEN..];
    if crc32fast::hash(payload) != crc {
        return Err(SnapshotError::Checksum);
    }
    let (state, rest) = postcard::take_from_bytes::<T>(payload)
        .map_err(|e| SnapshotError::Payload(e.to_string()))?;
    if !rest.is_empty() {
        return Err(SnapshotError::Payload(format!(
            "{} trailing bytes after the state",
            rest.len()
        )));
    }
    Ok(state)
}
