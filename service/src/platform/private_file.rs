//! Files only the service account and administrators may read: the token
//! file, the first-start admin token and the audit trail's folder. On Unix mode 0600; on Windows a
//! protected DACL granting full access to SYSTEM and Administrators only
//! (so the Users group of `%ProgramData%` cannot read or replace them).
//! Written to a temporary file that gets the permissions first, then
//! renamed over the target, so no reader ever sees a partial or open file.
//!
//! This is one of the two hand-written atomic writers (the other is the
//! channel's `ReplacedFile` in kuka-protocol, which must check the
//! controller's locks); other data files use the `atomic-write-file`
//! crate. It stays hand-written because the permissions must be on the
//! temporary file before its first byte, and on Windows they are set by
//! path, which that crate does not expose.

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically with private permissions.
pub fn write(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    let _ = std::fs::remove_file(&tmp);
    let result = (|| {
        let mut file = create(&tmp)?;
        restrict(&tmp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Makes a folder private to the service account and administrators (Unix
/// mode 0700; on Windows the same DACL as files, inherited by what is
/// created inside).
pub fn restrict_dir(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700))
    }
    #[cfg(windows)]
    {
        set_dacl(dir, PRIVATE_DIR_SDDL)
    }
    #[cfg(all(not(unix), not(windows)))]
    {
        let _ = dir;
        Ok(())
    }
}

#[cfg(unix)]
fn create(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)
}

#[cfg(not(unix))]
fn create(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
}

#[cfg(unix)]
fn restrict(_path: &Path) -> std::io::Result<()> {
    // Created with mode 0600 above.
    Ok(())
}

/// SYSTEM (SY) and the Administrators group (BA): full access; no
/// inherited entries (P).
#[cfg(windows)]
const PRIVATE_SDDL: &str = "D:P(A;;FA;;;SY)(A;;FA;;;BA)";

/// The same for a folder: object (OI) and container (CI) inherit.
#[cfg(windows)]
const PRIVATE_DIR_SDDL: &str = "D:P(A;OICI;FA;;;SY)(A;OICI;FA;;;BA)";

#[cfg(windows)]
fn restrict(path: &Path) -> std::io::Result<()> {
    set_dacl(path, PRIVATE_SDDL)
}

#[cfg(windows)]
#[allow(unsafe_code)]
fn set_dacl(path: &Path, sddl: &str) -> std::io::Result<()> {
    use std::os::windows::ffi::OsStrExt;
    use windows_sys::Win32::Foundation::LocalFree;
    use windows_sys::Win32::Security::Authorization::{
        ConvertStringSecurityDescriptorToSecurityDescriptorW, SDDL_REVISION_1,
    };
    use windows_sys::Win32::Security::{
        DACL_SECURITY_INFORMATION, PROTECTED_DACL_SECURITY_INFORMATION, PSECURITY_DESCRIPTOR,
        SetFileSecurityW,
    };
    let sddl: Vec<u16> = sddl.encode_utf16().chain(Some(0)).collect();
    let wide: Vec<u16> = path.as_os_str().encode_wide().chain(Some(0)).collect();
    let mut sd: PSECURITY_DESCRIPTOR = std::ptr::null_mut();
    // SAFETY: `sddl` is a NUL-terminated UTF-16 string that outlives the
    // call; `sd` receives a LocalAlloc'ed descriptor that we free below.
    let ok = unsafe {
        ConvertStringSecurityDescriptorToSecurityDescriptorW(
            sddl.as_ptr(),
            SDDL_REVISION_1,
            &mut sd,
            std::ptr::null_mut(),
        )
    };
    if ok == 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: `wide` is a NUL-terminated path and `sd` the valid
    // descriptor built above.
    let set = unsafe {
        SetFileSecurityW(
            wide.as_ptr(),
            DACL_SECURITY_INFORMATION | PROTECTED_DACL_SECURITY_INFORMATION,
            sd,
        )
    };
    let err = (set == 0).then(std::io::Error::last_os_error);
    // SAFETY: `sd` was allocated by the conversion above and is not used after.
    unsafe {
        LocalFree(sd);
    }
    err.map_or(Ok(()), Err)
}

#[cfg(all(not(unix), not(windows)))]
fn restrict(_path: &Path) -> std::io::Result<()> {
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    #[test]
    fn only_the_owner_reads() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("secret.txt");
        super::write(&p, b"x").expect("write");
        super::write(&p, b"y").expect("replace");
        let mode = std::fs::metadata(&p).expect("meta").permissions().mode();
        assert_eq!(mode & 0o777, 0o600);
        assert_eq!(std::fs::read(&p).expect("read"), b"y");
    }
}
