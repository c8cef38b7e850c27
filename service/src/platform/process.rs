//! Waiting for the service's process to be gone, not only "stopped".
//!
//! The service manager reports STOPPED just before the process exits, and
//! Windows cannot delete an executable while a process runs it. An
//! uninstall, upgrade or repair that removes `kuka-bridge.exe` right after
//! stopping the service (Wine's Windows Installer does not even wait for
//! STOPPED) must first wait here, or the file and its folder stay behind.

// Win32 calls: each unsafe block says why it is sound.
#![allow(unsafe_code)]

use std::path::Path;
use std::time::{Duration, Instant};

use windows_sys::Win32::Foundation::{CloseHandle, HANDLE, INVALID_HANDLE_VALUE, WAIT_TIMEOUT};
use windows_sys::Win32::System::Diagnostics::ToolHelp::{
    CreateToolhelp32Snapshot, PROCESSENTRY32W, Process32FirstW, Process32NextW, TH32CS_SNAPPROCESS,
};
use windows_sys::Win32::System::Threading::{
    GetCurrentProcessId, OpenProcess, PROCESS_NAME_WIN32, PROCESS_QUERY_LIMITED_INFORMATION,
    PROCESS_SYNCHRONIZE, QueryFullProcessImageNameW, WaitForSingleObject,
};

/// An owned Win32 handle, closed on drop.
struct Owned(HANDLE);

impl Owned {
    fn new(h: HANDLE) -> Option<Self> {
        (!h.is_null() && h != INVALID_HANDLE_VALUE).then_some(Self(h))
    }
}

impl Drop for Owned {
    fn drop(&mut self) {
        // SAFETY: the handle was returned open by the API and is closed once.
        unsafe { CloseHandle(self.0) };
    }
}

/// Ids of the processes other than this one whose image is `exe`
/// (compared without regard to case, like Windows paths).
pub fn running_image(exe: &Path) -> Vec<u32> {
    let Some(name) = exe.file_name().map(|n| n.to_string_lossy().to_lowercase()) else {
        return Vec::new();
    };
    let want = exe.to_string_lossy().to_lowercase();
    // SAFETY: plain Win32 calls; the entry is sized as the API requires.
    unsafe {
        let me = GetCurrentProcessId();
        let Some(snap) = Owned::new(CreateToolhelp32Snapshot(TH32CS_SNAPPROCESS, 0)) else {
            return Vec::new();
        };
        let mut entry = PROCESSENTRY32W {
            dwSize: std::mem::size_of::<PROCESSENTRY32W>() as u32,
            ..Default::default()
        };
        let mut found = Vec::new();
        let mut more = Process32FirstW(snap.0, &mut entry) != 0;
        while more {
            let pid = entry.th32ProcessID;
            let len = entry.szExeFile.iter().position(|&c| c == 0).unwrap_or(0);
            let entry_name = String::from_utf16_lossy(&entry.szExeFile[..len]).to_lowercase();
            if pid != me && entry_name == name {
                // A process whose path cannot be read (gone meanwhile, no
                // access) counts as ours: waiting too long beats deleting
                // nothing.
                if image_path(pid).is_none_or(|p| p.to_lowercase() == want) {
                    found.push(pid);
                }
            }
            more = Process32NextW(snap.0, &mut entry) != 0;
        }
        found
    }
}

/// The full path of a process's executable.
fn image_path(pid: u32) -> Option<String> {
    // SAFETY: plain Win32 calls with a buffer of the stated size.
    unsafe {
        let process = Owned::new(OpenProcess(PROCESS_QUERY_LIMITED_INFORMATION, 0, pid))?;
        let mut buf = [0u16; 1024];
        let mut len = buf.len() as u32;
        if QueryFullProcessImageNameW(process.0, PROCESS_NAME_WIN32, buf.as_mut_ptr(), &mut len)
            == 0
        {
            return None;
        }
        Some(String::from_utf16_lossy(&buf[..len as usize]))
    }
}

/// A process we may wait for, held open so its id cannot be reused for
/// another process meanwhile.
pub struct Process(Owned);

impl Process {
    /// Opens process `pid`; `None` if it is gone (or not ours to wait for).
    pub fn open(pid: u32) -> Option<Self> {
        // SAFETY: a plain Win32 call; the handle is owned by the result.
        Owned::new(unsafe { OpenProcess(PROCESS_SYNCHRONIZE, 0, pid) }).map(Process)
    }
}

/// Waits until every process in `processes` has exited, at most `within`
/// in all. Returns how many still run.
pub fn wait_exited(processes: &[Process], within: Duration) -> usize {
    let end = Instant::now() + within;
    processes
        .iter()
        .filter(|p| {
            let ms = end.saturating_duration_since(Instant::now()).as_millis();
            let ms = u32::try_from(ms).unwrap_or(u32::MAX);
            // SAFETY: waiting on a handle we own. WAIT_FAILED: nothing left
            // to wait on.
            unsafe { WaitForSingleObject(p.0.0, ms) == WAIT_TIMEOUT }
        })
        .count()
}
