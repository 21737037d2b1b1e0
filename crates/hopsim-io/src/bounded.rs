//! Bounded reads of input files: a regular file above the limit is refused unread; any
//! other input (a pipe, a device) is read in 64 KiB blocks up to the limit, so
//! `/dev/zero` or an endless stream costs at most the limit (docs/reliability.md).

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// What an input must look like, checked block by block as it is read.
#[derive(Clone, Copy, Debug)]
pub enum Content<'a> {
    /// Text: the first NUL byte ends the read with an error (`/dev/zero` costs one block).
    Text,
    /// Binary of the `format` (e.g. "MCAP") starting with `magic`, or else text (a NUL
    /// byte ends the read).
    MagicOrText { magic: &'a [u8], format: &'a str },
}

/// The bytes of `path`, at most `limit`; `what` names the kind of file in the error
/// (`"scene files"` gives "the file is larger than the 8 MiB limit of scene files").
pub fn read_bounded(
    path: &Path,
    limit: u64,
    what: &str,
    content: Content,
) -> Result<Vec<u8>, Error> {
    let too_large = || {
        Error::new(
            ErrorKind::FileTooLarge,
            format!(
                "the file is larger than the {} MiB limit of {what}",
                limit >> 20
            ),
        )
    };
    let mut file = std::fs::File::open(path)?;
    if file
        .metadata()
        .is_ok_and(|m| m.is_file() && m.len() > limit)
    {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    let mut block = vec![0u8; 1 << 16];
    // Whether the input starts with the magic (None until enough bytes are read).
    let mut binary = match content {
        Content::Text => Some(false),
        Content::MagicOrText { .. } => None,
    };
    let mut checked = 0;
    loop {
        let n = match file.read(&mut block) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if (bytes.len() + n) as u64 > limit {
            return Err(too_large());
        }
        bytes.extend_from_slice(&block[..n]);
        if let (None, Content::MagicOrText { magic, .. }) = (binary, content) {
            if bytes.len() >= magic.len() {
                binary = Some(bytes.starts_with(magic));
            }
        }
        if binary == Some(false) {
            if let Some(i) = bytes[checked..].iter().position(|&b| b == 0) {
                let offset = checked + i;
                let message = match content {
                    Content::Text => format!("not a text file (NUL byte at offset {offset})"),
                    Content::MagicOrText { format, .. } => format!(
                        "neither an {format} file (no {format} magic at the start) nor text (NUL byte at offset {offset})"
                    ),
                };
                return Err(Error::new(ErrorKind::InvalidData, message));
            }
            checked = bytes.len();
        }
    }
    Ok(bytes)
}

/// The text of `path`, at most `limit` bytes ([`read_bounded`]), which must be UTF-8.
pub fn read_text_bounded(path: &Path, limit: u64, what: &str) -> Result<String, Error> {
    let bytes = read_bounded(path, limit, what, Content::Text)?;
    String::from_utf8(bytes).map_err(|e| {
        Error::new(
            ErrorKind::InvalidData,
            format!(
                "not a text file (invalid UTF-8 at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}
