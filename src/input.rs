//! Reading the text files users give (automata, meshes, segment lists):
//! never past a size cap, never a binary file. `/dev/zero` or
//! `/dev/urandom` given as an automaton used to be read until memory ran out.

use std::io::Read as _;
use std::path::Path;

/// The largest text file read: 1 GiB (a generated automaton of a mesh of
/// 100,000 faces is about 400 MiB; an OBJ of ten million faces about 500 MiB).
pub const TEXT_FILE_LIMIT: u64 = 1 << 30;

/// The text of the file at `path`, read in pieces: refused (an
/// [`std::io::ErrorKind::InvalidData`] error saying why) at its first NUL
/// byte (a binary file, a device such as `/dev/zero`), past `limit` bytes,
/// or when it is not UTF-8. Files that only stream (pipes, devices) are
/// read the same way, since their size is not known before.
///
/// # Errors
/// The system's error opening or reading, or the refusals above.
pub fn read_text(path: &Path, limit: u64) -> std::io::Result<String> {
    let invalid = |message: String| std::io::Error::new(std::io::ErrorKind::InvalidData, message);
    let file = std::fs::File::open(path)?;
    if let Ok(meta) = file.metadata()
        && meta.is_file()
        && meta.len() > limit
    {
        return Err(invalid(format!(
            "{} bytes ({}), over the {} a text file may be: not an automaton or mesh file?",
            meta.len(),
            crate::progress::bytes_text(u128::from(meta.len())),
            crate::progress::bytes_text(u128::from(limit))
        )));
    }
    let mut bytes = Vec::new();
    let mut reader = file.take(limit + 1);
    let mut chunk = vec![0u8; 1 << 20];
    loop {
        let n = match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if let Some(at) = chunk[..n].iter().position(|&b| b == 0) {
            return Err(invalid(format!(
                "a NUL byte at byte {}: a binary file or a device, not text",
                bytes.len() + at
            )));
        }
        bytes.extend_from_slice(&chunk[..n]);
        if bytes.len() as u64 > limit {
            return Err(invalid(format!(
                "more than {} (read stopped there): not an automaton or mesh file?",
                crate::progress::bytes_text(u128::from(limit))
            )));
        }
    }
    String::from_utf8(bytes)
        .map_err(|e| invalid(format!("not UTF-8 text: an invalid byte at byte {}", e.utf8_error().valid_up_to())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_binary_and_oversized_files_are_refused_before_memory_runs_out() {
        let zero = read_text(Path::new("/dev/zero"), TEXT_FILE_LIMIT).unwrap_err();
        assert!(zero.to_string().contains("NUL byte at byte 0"), "{zero}");
        let random = read_text(Path::new("/dev/urandom"), TEXT_FILE_LIMIT).unwrap_err();
        assert_eq!(random.kind(), std::io::ErrorKind::InvalidData, "{random}");
        let dir = std::env::temp_dir().join(format!("bcifs-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let big = dir.join("big.toml");
        std::fs::write(&big, "x".repeat(5000)).unwrap();
        let e = read_text(&big, 4096).unwrap_err();
        assert!(e.to_string().contains("5000 bytes (5 KiB), over the 4 KiB"), "{e}");
        assert_eq!(read_text(&big, 5000).unwrap().len(), 5000);
        std::fs::write(&big, b"name = \"a\"\n\xff").unwrap();
        assert!(read_text(&big, 4096).unwrap_err().to_string().contains("not UTF-8 text: an invalid byte at byte 11"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
