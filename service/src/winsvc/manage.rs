//! `kuka-bridge service install | uninstall | start | stop | status`:
//! everything a Windows installation needs, from the binary, so no one
//! edits the registry by hand and the MSI can call the same steps.

use std::ffi::OsString;
use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use windows_service::service::{
    ServiceAccess, ServiceAction, ServiceActionType, ServiceErrorControl, ServiceExitCode,
    ServiceFailureActions, ServiceFailureResetPeriod, ServiceInfo, ServiceStartType, ServiceState,
    ServiceType,
};
use windows_service::service_manager::{ServiceManager, ServiceManagerAccess};
use winreg::RegKey;
use winreg::enums::{HKEY_LOCAL_MACHINE, KEY_ALL_ACCESS, REG_EXPAND_SZ};

use super::{DESCRIPTION, DISPLAY_NAME, EVENT_SOURCE, SERVICE_NAME, config_path, program_data};
use crate::config::Config;
use crate::platform::process::{Process, running_image, wait_exited};

/// Where Event Log sources of the Application log are registered.
const EVENTLOG_KEY: &str = r"SYSTEM\CurrentControlSet\Services\EventLog\Application";

/// `ERROR_SERVICE_DOES_NOT_EXIST`.
const NO_SUCH_SERVICE: i32 = 1060;

fn manager(create: bool) -> Result<ServiceManager> {
    let access = if create {
        ServiceManagerAccess::CONNECT | ServiceManagerAccess::CREATE_SERVICE
    } else {
        ServiceManagerAccess::CONNECT
    };
    ServiceManager::local_computer(None::<&str>, access)
        .context("cannot connect to the service manager (run as administrator)")
}

fn is_missing(e: &windows_service::Error) -> bool {
    matches!(e, windows_service::Error::Winapi(io) if io.raw_os_error() == Some(NO_SUCH_SERVICE))
}

/// Installs or updates the service and everything around it; starts it if
/// `start`. With `from_msi`, the MSI has created the service: only its
/// configuration (description, recovery) and the files are done here.
pub fn install(start: bool, from_msi: bool) -> Result<()> {
    let exe = std::env::current_exe().context("cannot find this executable's path")?;
    let info = ServiceInfo {
        name: OsString::from(SERVICE_NAME),
        display_name: OsString::from(DISPLAY_NAME),
        service_type: ServiceType::OWN_PROCESS,
        start_type: ServiceStartType::AutoStart,
        error_control: ServiceErrorControl::Normal,
        executable_path: exe.clone(),
        launch_arguments: vec![
            OsString::from("service"),
            OsString::from("run"),
            OsString::from("--config"),
            config_path().into_os_string(),
        ],
        dependencies: vec![],
        account_name: None, // LocalSystem: the channel folder belongs to the KRC's users
        account_password: None,
    };
    let access = ServiceAccess::QUERY_STATUS
        | ServiceAccess::CHANGE_CONFIG
        | ServiceAccess::START
        | ServiceAccess::STOP;
    let sm = manager(true)?;
    let service = match sm.open_service(SERVICE_NAME, access) {
        Ok(s) => {
            if !from_msi {
                s.change_config(&info)
                    .context("cannot update the service")?;
                println!("service {SERVICE_NAME}: updated ({})", exe.display());
            }
            s
        }
        Err(e) if is_missing(&e) && !from_msi => {
            let s = sm
                .create_service(&info, access)
                .context("cannot create the service")?;
            println!("service {SERVICE_NAME}: created ({})", exe.display());
            s
        }
        Err(e) => return Err(e).context("cannot open the service"),
    };
    service
        .set_description(DESCRIPTION)
        .context("cannot set the service description")?;
    // Recovery: restart after 5 s, 30 s, 5 min; forget failures after a day;
    // also when the service stops itself with an error exit code.
    let actions = ServiceFailureActions {
        reset_period: ServiceFailureResetPeriod::After(Duration::from_secs(24 * 3600)),
        reboot_msg: None,
        command: None,
        actions: Some(
            [5, 30, 300]
                .into_iter()
                .map(|s| ServiceAction {
                    action_type: ServiceActionType::Restart,
                    delay: Duration::from_secs(s),
                })
                .collect(),
        ),
    };
    let recovery = service
        .update_failure_actions(actions)
        .and_then(|()| service.set_failure_actions_on_non_crash_failures(true));
    match recovery {
        Ok(()) => println!("recovery: restart after 5 s, 30 s, 5 min; reset after 1 day"),
        // Wine does not implement failure actions (error 124); Windows does.
        Err(e) => {
            tracing::warn!(error = %e, "cannot set the recovery actions (Wine does not implement them); set them in services.msc")
        }
    }
    register_event_source(&exe)?;
    prepare_program_data()?;
    if start {
        start_service(&service)?;
    }
    Ok(())
}

fn register_event_source(_exe: &Path) -> Result<()> {
    let hklm = RegKey::predef(HKEY_LOCAL_MACHINE);
    let (key, _) = hklm
        .create_subkey(format!(r"{EVENTLOG_KEY}\{EVENT_SOURCE}"))
        .context("cannot register the Event Log source (run as administrator)")?;
    // EventCreate.exe's messages are the text itself (ids 1-1000).
    let file = r"%SystemRoot%\System32\EventCreate.exe";
    let bytes: Vec<u8> = file
        .encode_utf16()
        .chain(std::iter::once(0))
        .flat_map(u16::to_le_bytes)
        .collect();
    key.set_raw_value(
        "EventMessageFile",
        &winreg::RegValue {
            bytes: bytes.into(),
            vtype: REG_EXPAND_SZ,
        },
    )
    .context("cannot write EventMessageFile")?;
    key.set_value("TypesSupported", &7u32)
        .context("cannot write TypesSupported")?;
    println!("Event Log source {EVENT_SOURCE} registered (Application log)");
    Ok(())
}

fn prepare_program_data() -> Result<()> {
    let root = program_data();
    for sub in ["logs", "plugins", "programs"] {
        let d = root.join(sub);
        std::fs::create_dir_all(&d).with_context(|| format!("cannot create {}", d.display()))?;
    }
    restrict(&root);
    let path = config_path();
    if path.exists() {
        println!("config kept: {}", path.display());
    } else {
        let mut text = String::from(
            "# kuka-bridge service configuration (every key is optional; see README.md).\n\
             # Restart the service after a change: kuka-bridge service stop / start.\n",
        );
        let mut config = Config::default();
        // On a KRC the channel is the controller's user files folder.
        let krc = Path::new(r"C:\KRC\ROBOTER\UserFiles");
        if krc.is_dir() {
            config.channel.dir = Some(krc.to_path_buf());
        } else {
            println!(
                "no {} here: set [channel] dir in the config to the controller's channel folder",
                krc.display()
            );
        }
        text.push_str(&toml::to_string_pretty(&config).context("default config")?);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
        println!("default config written: {}", path.display());
    }
    Ok(())
}

/// Full control for SYSTEM and Administrators only: configuration, tokens
/// and plugins live here, and the service runs as SYSTEM. Best effort: a
/// failure is logged.
fn restrict(dir: &Path) {
    let out = std::process::Command::new("icacls")
        .arg(dir)
        .args([
            "/inheritance:r",
            "/grant:r",
            "*S-1-5-18:(OI)(CI)F",
            "/grant:r",
            "*S-1-5-32-544:(OI)(CI)F",
        ])
        .output();
    match out {
        Ok(o) if o.status.success() => {
            println!(
                "permissions of {}: SYSTEM and Administrators only",
                dir.display()
            )
        }
        Ok(o) => tracing::warn!(
            dir = %dir.display(),
            output = %String::from_utf8_lossy(&o.stderr),
            "icacls could not restrict the folder"
        ),
        Err(e) => tracing::warn!(dir = %dir.display(), error = %e, "cannot run icacls"),
    }
}

fn start_service(service: &windows_service::service::Service) -> Result<()> {
    let s = service.query_status().context("cannot query the service")?;
    if s.current_state != ServiceState::Running {
        service
            .start::<OsString>(&[])
            .context("cannot start the service")?;
    }
    wait_for(service, ServiceState::Running, Duration::from_secs(30))?;
    println!("service {SERVICE_NAME}: running");
    Ok(())
}

fn wait_for(
    service: &windows_service::service::Service,
    want: ServiceState,
    within: Duration,
) -> Result<()> {
    let end = Instant::now() + within;
    loop {
        let s = service.query_status().context("cannot query the service")?;
        if s.current_state == want {
            return Ok(());
        }
        if s.current_state == ServiceState::Stopped && want == ServiceState::Running {
            anyhow::bail!(
                "the service stopped while starting (exit code {}); see the log in {}",
                exit_code(&s.exit_code),
                program_data().join("logs").display()
            );
        }
        if Instant::now() > end {
            anyhow::bail!(
                "the service is still {:?} after {within:?}",
                s.current_state
            );
        }
        std::thread::sleep(Duration::from_millis(200));
    }
}

fn exit_code(c: &ServiceExitCode) -> String {
    match c {
        ServiceExitCode::Win32(n) => format!("win32 {n}"),
        ServiceExitCode::ServiceSpecific(n) => format!("service-specific {n}"),
    }
}

/// Stops and deletes the service and its Event Log source; `purge` also
/// deletes `%ProgramData%\kuka-bridge`.
pub fn uninstall(purge: bool, from_msi: bool) -> Result<()> {
    if !from_msi {
        let sm = manager(false)?;
        let access = ServiceAccess::QUERY_STATUS | ServiceAccess::STOP | ServiceAccess::DELETE;
        match sm.open_service(SERVICE_NAME, access) {
            Ok(service) => {
                if service.query_status()?.current_state != ServiceState::Stopped {
                    let _ = service.stop();
                    wait_for(&service, ServiceState::Stopped, Duration::from_secs(60))?;
                }
                service.delete().context("cannot delete the service")?;
                println!("service {SERVICE_NAME}: removed");
            }
            Err(e) if is_missing(&e) => println!("service {SERVICE_NAME}: not installed"),
            Err(e) => return Err(e).context("cannot open the service"),
        }
    }
    let hklm = RegKey::predef(HKEY_LOCAL_MACHINE);
    if let Ok(app) = hklm.open_subkey_with_flags(EVENTLOG_KEY, KEY_ALL_ACCESS) {
        match app.delete_subkey_all(EVENT_SOURCE) {
            Ok(()) => println!("Event Log source {EVENT_SOURCE}: removed"),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => tracing::warn!(error = %e, "cannot remove the Event Log source"),
        }
    }
    let data = program_data();
    if purge {
        match std::fs::remove_dir_all(&data) {
            Ok(()) => println!("removed {}", data.display()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(e).with_context(|| format!("cannot remove {}", data.display())),
        }
    } else if data.exists() {
        println!(
            "kept {} (config, logs, data); --purge removes it",
            data.display()
        );
    }
    Ok(())
}

fn open(access: ServiceAccess) -> Result<windows_service::service::Service> {
    manager(false)?
        .open_service(SERVICE_NAME, access)
        .map_err(|e| {
            if is_missing(&e) {
                anyhow::anyhow!("the service is not installed (kuka-bridge service install)")
            } else {
                anyhow::Error::new(e).context("cannot open the service")
            }
        })
}

/// Starts the service and waits until it runs.
pub fn start() -> Result<()> {
    start_service(&open(ServiceAccess::QUERY_STATUS | ServiceAccess::START)?)
}

/// How long a stop may take before the CLI or the MSI gives up waiting:
/// the service's own shutdown budget is a few seconds.
const STOP_WAIT: Duration = Duration::from_secs(60);

/// Stops the service and waits until its process has exited, so its
/// executable can be replaced or deleted at once.
pub fn stop() -> Result<()> {
    let service = open(ServiceAccess::QUERY_STATUS | ServiceAccess::STOP)?;
    let status = service.query_status()?;
    // Held from before the stop: its id cannot go to another process.
    let process = status.process_id.and_then(Process::open);
    if status.current_state != ServiceState::Stopped {
        service.stop().context("cannot stop the service")?;
        wait_for(&service, ServiceState::Stopped, STOP_WAIT)?;
    }
    if wait_exited(process.as_slice(), STOP_WAIT) > 0 {
        anyhow::bail!(
            "the service reports STOPPED but its process {:?} still runs after {STOP_WAIT:?}",
            status.process_id
        );
    }
    println!("service {SERVICE_NAME}: stopped");
    Ok(())
}

/// The MSI's step before it deletes or overwrites `kuka-bridge.exe`
/// (uninstall, upgrade, repair): its StopServices has asked the service to
/// stop; wait until no process runs this executable any more. Never fails
/// the installation: what is still running is reported and the MSI goes on.
pub fn stop_for_msi() -> Result<()> {
    if let Ok(service) = open(ServiceAccess::QUERY_STATUS | ServiceAccess::STOP)
        && service
            .query_status()
            .is_ok_and(|s| s.current_state == ServiceState::Running)
    {
        let _ = service.stop();
    }
    let exe = std::env::current_exe().context("cannot locate this executable")?;
    let running: Vec<Process> = running_image(&exe)
        .into_iter()
        .filter_map(Process::open)
        .collect();
    match wait_exited(&running, STOP_WAIT) {
        0 => println!("no process runs {} any more", exe.display()),
        n => println!(
            "{n} process(es) still run {} after {STOP_WAIT:?}",
            exe.display()
        ),
    }
    Ok(())
}

/// Prints the state, process, exit codes and where config and logs are.
pub fn status() -> Result<()> {
    let service = open(ServiceAccess::QUERY_STATUS)?;
    let s = service.query_status()?;
    println!("service:  {SERVICE_NAME} ({DISPLAY_NAME})");
    println!("state:    {:?}", s.current_state);
    if let Some(pid) = s.process_id {
        println!("process:  {pid}");
    }
    println!("exit:     {}", exit_code(&s.exit_code));
    println!("config:   {}", config_path().display());
    println!("logs:     {}", program_data().join("logs").display());
    Ok(())
}
