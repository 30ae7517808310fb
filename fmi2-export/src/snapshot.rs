//! The serialized FMU state: a fixed little-endian header followed by a postcard payload.
//!
//! ```text
//! offset size field
//!      0    8 magic "FMI2SNAP"
//!      8    2 format version (this layout) = 1
//!     10    2 reserved, 0
//!     12    4 Model::STATE_VERSION
//!     16   16 interface GUID of the model (binary UUID): a foreign FMU's buffer is refused
//!     32    8 payload length in bytes
//!     40    4 CRC-32 (IEEE) of the payload
//!     44    n payload: postcard encoding of `Core<M>` (f64 as raw bits: round trip is exact)
//! ```
//! Every field is checked before the payload is decoded, and the buffer length must equal
//! header + payload exactly; reads go through bounds-checked slices only.
use crate::instance::Core;
use crate::model::Model;
use uuid::Uuid;

const MAGIC: [u8; 8] = *b"FMI2SNAP";
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

pub fn encode<M: Model>(core: &Core<M>, guid: Uuid) -> Result<Vec<u8>, SnapshotError> {
    let payload = postcard::to_allocvec(core).map_err(|e| SnapshotError::Encode(e.to_string()))?;
    let mut bytes = Vec::with_capacity(HEADER_LEN + payload.len());
    bytes.extend_from_slice(&MAGIC);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&0u16.to_le_bytes());
    bytes.extend_from_slice(&M::STATE_VERSION.to_le_bytes());
    bytes.extend_from_slice(guid.as_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    debug_assert_eq!(bytes.len(), HEADER_LEN);
    bytes.extend_from_slice(&payload);
    Ok(bytes)
}

pub fn decode<M: Model>(bytes: &[u8], guid: Uuid) -> Result<Core<M>, SnapshotError> {
    let header = bytes
        .get(..HEADER_LEN)
        .ok_or(SnapshotError::TooShort { len: bytes.len() })?;
    let field = |at: usize, n: usize| &header[at..at + n];
    if field(0, 8) != MAGIC {
        return Err(SnapshotError::BadMagic);
    }
    let format = u16::from_le_bytes(field(8, 2).try_into().expect("2 bytes"));
    if format != FORMAT_VERSION {
        return Err(SnapshotError::FormatVersion { found: format });
    }
    let state_version = u32::from_le_bytes(field(12, 4).try_into().expect("4 bytes"));
    if state_version != M::STATE_VERSION {
        return Err(SnapshotError::StateVersion {
            found: state_version,
            expected: M::STATE_VERSION,
        });
    }
    let found = Uuid::from_slice(field(16, 16)).expect("16 bytes");
    if found != guid {
        return Err(SnapshotError::ForeignGuid {
            found,
            expected: guid,
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
    let (core, rest) = postcard::take_from_bytes::<Core<M>>(payload)
        .map_err(|e| SnapshotError::Payload(e.to_string()))?;
    if !rest.is_empty() {
        return Err(SnapshotError::Payload(format!(
            "{} trailing bytes after the state",
            rest.len()
        )));
    }
    Ok(core)
}
