#pragma once
// A fatal signal (SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT) reported on stderr before the
// process dies: the signal, the faulting address, the thread's name and a backtrace of raw
// return addresses ("probeless(+0x1a2b3c)"), which `addr2line -fCe probeless 0x1a2b3c`
// resolves on the development machine. Under systemd the lines go to the journal with
// priority 2 (crit). The handler then restores the default action and re-raises, so the exit
// status still says "killed by SIGSEGV" (Restart=, coredumps) and nothing is swallowed.
//
// Why: one segfault of `probeless run` in the VM board check (session 12) left nothing to
// diagnose it with; an appliance in the field has no debugger attached either.
//
// The handler runs on its own alternate stack (a stack overflow still reports) and does only
// async-signal-safe work, with one exception documented by glibc: backtrace() may load
// libgcc on first use, so install() calls it once beforehand.
namespace probeless {

// Installs the handler for the fatal signals, once per process (later calls do nothing).
// `program` names the process in the report.
void install_crash_report(const char* program);

}  // namespace probeless
