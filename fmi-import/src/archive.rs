//! Where an FMU's files are: the workspace's one unpacker (`fmi-abi`), its errors told in the
//! loader's terms.
use super::error::LoadError;
use fmi_abi::unpack::UnpackError;
pub(crate) use fmi_abi::unpack::Unpacked;
pub(crate) use fmi_abi::unpack::FMI2_PLATFORM as PLATFORM;

impl From<UnpackError> for LoadError {
    fn from(e: UnpackError) -> LoadError {
        match e {
            UnpackError::Io { path, source } => LoadError::Io { path, source },
            UnpackError::Zip { path, source } => LoadError::Zip { path, source },
            UnpackError::MissingModelDescription { path } => {
                LoadError::MissingModelDescription { path }
            }
            other => LoadError::Unpack(other),
        }
    }
}
