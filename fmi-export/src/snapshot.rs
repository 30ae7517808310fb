//! The serialized FMU state: a fixed little-endian header followed by a postcard payload.
//!
//! ```text
//! offset size field
//!      0    8 magic, chosen by the layer (FMI 2.0: "FMI2SNAP")
//!      8    2 format version (this layout) = 2
//!     10    1 interface the state was taken from: 1 Co-Simulation, 2 Model Exchange
//!     11    1 reserved, 0
//!     12    4 Model::STATE_VERSION
//!     16   16 interface GUID of the model (binary UUID): a foreign FMU's buffer is refused
//!     32    8 payload length in bytes
//!     40    4 CRC-32 (IEEE) of the payload
//!     44    n payload: postcard encoding of the layer's state (f64 as raw bits: exact)
//! ```
//! Every field is checked before the payload is decoded, and the buffer length must equal
//! header + payload exactly; reads go through bounds-checked slices only.
//!
//! The interface is recorded because a layer serializes the instances of both interfaces
//! as one type: a Model Exchange state would decode in a Co-Simulation instance (and the
//! reverse) and leave it in a state of the other interface's. The reserved byte must be 0:
//! a buffer with anything else there was not written in this format. Format 1 (bytes 10 and
//! 11 both reserved, no interface) is refused by its version.
use fmi_model::Interface;
use serde::{de::DeserializeOwned, Serialize};
use uuid::Uuid;

const FORMAT_VERSION: u16 = 2;
pub const HEADER_LEN: usize = 44;
/// Where the interface byte and the reserved byte are.
const INTERFACE_AT: usize = 10;
const RESERVED_AT: usize = 11;

/// The interface's byte in the header; 0 is no interface, so a zeroed header is refused.
const fn interface_code(interface: Interface) -> u8 {
    match interface {
        Interface::CoSimulation => 1,
        Interface::ModelExchange => 2,
    }
}

fn interface_of(code: u8) -> Option<Interface> {
    [Interface::CoSimulation, Interface::ModelExchange]
        .into_iter()
        .find(|&i| interface_code(i) == code)
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SnapshotError {
    #[error("buffer of {len} bytes is shorter than the {HEADER_LEN}-byte header")]
    TooShort { len: usize },
    #[error("buffer does not start with the FMU-state magic bytes")]
    BadMagic,
    #[error("format version {found}, this FMU reads version {FORMAT_VERSION}")]
    FormatVersion { found: u16 },
    #[error("reserved header byte {at} is {value}, must be 0")]
    Reserved { at: usize, value: u8 },
    #[error("interface byte {code} is neither Co-Simulation (1) nor Model Exchange (2)")]
    UnknownInterface { code: u8 },
    #[error("state of a {found} instance; this instance is {expected}")]
    OtherInterface {
        found: Interface,
        expected: Interface,
    },
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

/// What identifies a buffer as ours: the layer's magic bytes, the model's state version,
/// the interface GUID, and the interface of the instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    pub magic: [u8; 8],
    pub state_version: u32,
    pub guid: Uuid,
    pub interface: Interface,
}

pub fn encode<T: Serialize>(state: &T, header: Header) -> Result<Vec<u8>, SnapshotError> {
    let Header {
        magic,
        state_version,
        guid,
        interface,
    } = header;
    let payload = postcard::to_allocvec(state).map_err(|e| SnapshotError::Encode(e.to_string()))?;
    let mut bytes = Vec::with_capacity(HEADER_LEN + payload.len());
    bytes.extend_from_slice(&magic);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    bytes.push(interface_code(interface));
    bytes.push(0);
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
        interface: expected_interface,
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
    if header[RESERVED_AT] != 0 {
        return Err(SnapshotError::Reserved {
            at: RESERVED_AT,
            value: header[RESERVED_AT],
        });
    }
    let code = header[INTERFACE_AT];
    let interface = interface_of(code).ok_or(SnapshotError::UnknownInterface { code })?;
    // Which FMU first: a state of another FMU is that, whatever its version.
    let found = Uuid::from_slice(field(16, 16)).expect("16 bytes");
    if found != guid {
        return Err(SnapshotError::ForeignGuid {
            found,
            expected: guid,
        });
    }
    if interface != expected_interface {
        return Err(SnapshotError::OtherInterface {
            found: interface,
            expected: expected_interface,
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

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: Header = Header {
        magic: *b"TESTSNAP",
        state_version: 7,
        guid: Uuid::from_u128(0x1234_5678_9abc_def0_1234_5678_9abc_def0),
        interface: Interface::CoSimulation,
    };

    fn sealed() -> Vec<u8> {
        encode(&(1.5f64, -3i32, String::from("x")), HEADER).unwrap()
    }

    fn refusal(bytes: &[u8], header: Header) -> String {
        decode::<(f64, i32, String)>(bytes, header)
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn a_state_round_trips_under_either_interface() {
        for interface in [Interface::CoSimulation, Interface::ModelExchange] {
            let header = Header {
                interface,
                ..HEADER
            };
            let bytes = encode(&(f64::MIN_POSITIVE, 42u8), header).unwrap();
            assert_eq!(bytes[INTERFACE_AT], interface_code(interface));
            assert_eq!(bytes[RESERVED_AT], 0);
            assert_eq!(
                decode::<(f64, u8)>(&bytes, header),
                Ok((f64::MIN_POSITIVE, 42))
            );
        }
        assert_eq!(&sealed()[8..10], &FORMAT_VERSION.to_le_bytes());
    }

    #[test]
    fn a_state_of_the_other_interface_is_refused_by_name() {
        let model_exchange = Header {
            interface: Interface::ModelExchange,
            ..HEADER
        };
        assert_eq!(
            refusal(&sealed(), model_exchange),
            "state of a Co-Simulation instance; this instance is Model Exchange"
        );
        let bytes = encode(&(0.0f64, 0i32, String::new()), model_exchange).unwrap();
        assert_eq!(
            refusal(&bytes, HEADER),
            "state of a Model Exchange instance; this instance is Co-Simulation"
        );
    }

    #[test]
    fn a_nonzero_reserved_byte_is_refused() {
        let mut bytes = sealed();
        bytes[RESERVED_AT] = 0x80;
        assert_eq!(
            refusal(&bytes, HEADER),
            "reserved header byte 11 is 128, must be 0"
        );
    }

    #[test]
    fn an_interface_byte_of_no_interface_is_refused() {
        for code in [0, 3, 0xff] {
            let mut bytes = sealed();
            bytes[INTERFACE_AT] = code;
            assert_eq!(
                refusal(&bytes, HEADER),
                format!(
                    "interface byte {code} is neither Co-Simulation (1) nor Model Exchange (2)"
                )
            );
        }
    }

    #[test]
    fn a_state_of_the_previous_format_is_refused() {
        // Format 1: bytes 10 and 11 both reserved, 0.
        let mut bytes = sealed();
        bytes[8..10].copy_from_slice(&1u16.to_le_bytes());
        bytes[INTERFACE_AT] = 0;
        assert_eq!(
            refusal(&bytes, HEADER),
            "format version 1, this FMU reads version 2"
        );
    }

    #[test]
    fn a_foreign_fmu_is_named_before_the_interface() {
        let other = Header {
            guid: Uuid::nil(),
            interface: Interface::ModelExchange,
            ..HEADER
        };
        assert!(refusal(&sealed(), other).starts_with("state of a different FMU"));
    }

    #[test]
    fn resealing_keeps_the_interface() {
        let bytes = reseal(
            &sealed(),
            &postcard::to_allocvec(&(2.0f64, 1i32, "y")).unwrap(),
        );
        assert_eq!(
            decode::<(f64, i32, String)>(&bytes, HEADER),
            Ok((2.0, 1, "y".into()))
        );
        let model_exchange = Header {
            interface: Interface::ModelExchange,
            ..HEADER
        };
        assert!(matches!(
            decode::<(f64, i32, String)>(&bytes, model_exchange),
            Err(SnapshotError::OtherInterface { .. })
        ));
    }
}
