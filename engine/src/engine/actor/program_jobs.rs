//! Program jobs: after the dry run, the module written into the
//! controller's program folder and the RUN command sent.

use super::*;

impl Actor {
    /// A program job's dry run has finished: send it, or fail it.
    pub(super) fn program_checked(
        &mut self,
        job: QueuedJob,
        result: Result<crate::safety::ProgramCheck>,
    ) {
        if self.checking != Some(job.id) {
            return; // cancelled meanwhile
        }
        self.checking = None;
        let id = job.id;
        let sent = result.and_then(|check| {
            let Operation::RunProgram(program) = &job.op else {
                return Err(BridgeError::new(ErrorCode::Internal, "not a program job"));
            };
            if check.checked && !check.complete {
                tracing::warn!(
                    program = %program.info.name,
                    steps = check.steps,
                    "program does not end within the dry run's limits; checked up to there"
                );
            }
            if !check.checked {
                tracing::info!(
                    program = %program.info.name,
                    "program sent without a dry run (no robot model, or KRL beyond the simulator's subset)"
                );
            }
            if let Some(n) = check.steps.filter(|_| check.complete) {
                self.shared.update(id, |j| j.motions = n);
            }
            if !self.ctl.online {
                return Err(BridgeError::new(
                    ErrorCode::ControllerOffline,
                    "the controller went offline during the dry run; nothing was sent",
                ));
            }
            let dir = self.program_dir.clone().ok_or_else(|| {
                BridgeError::new(ErrorCode::ProgramsUnavailable, "no program folder is configured")
            })?;
            let program = program.clone();
            let cid = self.next_cid()?;
            self.write_module(&dir, cid, &program)?;
            let timeout = job.timeout.unwrap_or(self.cfg.command_timeout);
            self.write(
                CommandFile {
                    cid,
                    command: Command::Run(cid),
                },
                Some((job, timeout)),
            );
            Ok(())
        });
        if let Err(e) = sent {
            tracing::warn!(job = id, code = e.code.as_str(), detail = %e.detail, "job not sent");
            self.shared.finish(id, JobState::Failed, e);
        }
    }

    /// Writes module `kbu<cid>` into the program folder and deletes the
    /// oldest generated modules beyond `keep_modules`.
    pub(super) fn write_module(
        &self,
        dir: &std::path::Path,
        cid: Cid,
        program: &crate::programs::StoredProgram,
    ) -> Result<()> {
        let m = crate::programs::module_text(cid, program);
        let fail = |e: &dyn std::fmt::Display| {
            tracing::error!(module = %m.name, dir = %dir.display(), error = %e, "program module not written");
            BridgeError::new(
                ErrorCode::ProgramsUnavailable,
                format!(
                    "cannot write module {} into the controller's program folder (programs.controller_dir); the service log says why",
                    m.name
                ),
            )
        };
        std::fs::create_dir_all(dir).map_err(|e| fail(&e))?;
        let tag = format!("svc{}", std::process::id());
        // KRL files on a KRC use the 8-bit Windows code page.
        let ansi = crate::programs::encode_ansi;
        kuka_protocol::files::atomic_write_bytes(
            dir,
            &format!("{}.src", m.name),
            &tag,
            &ansi(&m.src),
        )
        .map_err(|e| fail(&e))?;
        if let Some(dat) = &m.dat {
            kuka_protocol::files::atomic_write_bytes(
                dir,
                &format!("{}.dat", m.name),
                &tag,
                &ansi(dat),
            )
            .map_err(|e| fail(&e))?;
        }
        tracing::info!(module = %m.name, program = %program.info.name, "program module written");
        // Keep the newest modules only (by number; ours are the only kbu* files).
        let mut numbers: Vec<i64> = std::fs::read_dir(dir)
            .map(|rd| {
                rd.flatten()
                    .filter_map(|e| {
                        let name = e.file_name().to_string_lossy().into_owned();
                        name.strip_prefix("kbu")?.strip_suffix(".src")?.parse().ok()
                    })
                    .collect()
            })
            .unwrap_or_default();
        numbers.sort_unstable();
        let excess = numbers.len().saturating_sub(self.keep_modules.max(1));
        for n in &numbers[..excess] {
            for ext in ["src", "dat"] {
                let _ = std::fs::remove_file(dir.join(format!("kbu{n}.{ext}")));
            }
        }
        Ok(())
    }
}
