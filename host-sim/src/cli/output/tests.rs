//! Outputs: all or none, one file once, and never a file the command reads.

use super::*;

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("polyturn-out-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn one_unwritable_file_writes_none() {
    let d = dir("none");
    let mut o = Outputs::default();
    o.add("table", &d.join("t.json"), "{}".into()).unwrap();
    o.add("svg", Path::new("/nonexistent-dir/x.svg"), "<svg/>".into()).unwrap();
    let e = o.write().unwrap_err();
    assert!(e.0.starts_with("--svg could not write '/nonexistent-dir/x.svg'"), "{}", e.0);
    assert!(!d.join("t.json").exists());
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "no temporary left behind");
}

#[test]
fn two_flags_naming_one_file_are_refused() {
    let d = dir("same");
    let mut o = Outputs::default();
    o.add("table", &d.join("f"), "a".into()).unwrap();
    assert!(o
        .add("svg", &d.join(".").join("f"), "b".into())
        .unwrap_err()
        .0
        .starts_with("--svg names the same file as --table"));
}

#[test]
fn a_directory_is_refused_before_anything_is_written() {
    let d = dir("isdir");
    let mut o = Outputs::default();
    o.add("table", &d.join("t.json"), "{}".into()).unwrap();
    assert!(o.add("svg", &d, "<svg/>".into()).unwrap_err().0.starts_with("--svg must name a file"));
    assert!(o.add("svg", Path::new(".."), "<svg/>".into()).is_err());
    let mut o = Outputs::default();
    o.add("svg", Path::new("/nonexistent-dir/a\nb"), String::new()).unwrap();
    let e = o.write();
    assert_eq!(e.unwrap_err().0.lines().count(), 1, "the path's newline is escaped");
}

#[test]
fn all_files_are_written_when_all_can_be() {
    let d = dir("all");
    let mut o = Outputs::default();
    o.add("table", &d.join("t.json"), "{}".into()).unwrap();
    o.add("svg", &d.join("x.svg"), "<svg/>".into()).unwrap();
    o.write().unwrap();
    assert_eq!(std::fs::read_to_string(d.join("x.svg")).unwrap(), "<svg/>");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 2);
}

#[cfg(unix)]
#[test]
fn an_output_that_is_the_input_is_refused_however_spelt() {
    let d = dir("input");
    std::fs::write(d.join("fw.elf"), "elf").unwrap();
    std::fs::hard_link(d.join("fw.elf"), d.join("hard")).unwrap();
    let _ = std::os::unix::fs::symlink("fw.elf", d.join("soft"));
    for spelt in [d.join("fw.elf"), d.join(".").join("fw.elf"), d.join("hard"), d.join("soft")] {
        let mut o = Outputs::default();
        o.reading("ELF", &d.join("fw.elf"));
        let e = o.add_bytes("bin", &spelt, vec![1]).unwrap_err();
        assert!(e.0.starts_with("--bin must not be the ELF it reads (got '"), "{}", e.0);
    }
    assert_eq!(std::fs::read_to_string(d.join("fw.elf")).unwrap(), "elf");
}

#[cfg(target_os = "linux")]
#[test]
fn a_device_that_refuses_the_write_leaves_the_regular_files_as_they_were() {
    let d = dir("full");
    std::fs::write(d.join("t.json"), "old").unwrap();
    let mut o = Outputs::default();
    o.add("table", &d.join("t.json"), "new".into()).unwrap();
    o.add("svg", Path::new("/dev/full"), "<svg/>".into()).unwrap();
    let e = o.write().unwrap_err();
    assert!(e.0.starts_with("--svg could not write '/dev/full': No space left on device"), "{}", e.0);
    assert_eq!(std::fs::read_to_string(d.join("t.json")).unwrap(), "old");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "no temporary left behind");
}

#[cfg(unix)]
#[test]
fn a_replaced_file_keeps_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let d = dir("mode");
    let private = d.join("private.svg");
    std::fs::write(&private, "old").unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
    let mut o = Outputs::default();
    o.add("svg", &private, "<svg/>".into()).unwrap();
    o.write().unwrap();
    assert_eq!(std::fs::read_to_string(&private).unwrap(), "<svg/>");
    assert_eq!(std::fs::metadata(&private).unwrap().permissions().mode() & 0o777, 0o600);
}

/// What a directory holds besides `keep`: no temporary left, nothing new.
#[cfg(unix)]
fn only(d: &Path, names: &[&str]) {
    let mut found: Vec<String> =
        std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    found.sort();
    assert_eq!(found, names, "in {}", d.display());
}

#[cfg(unix)]
#[test]
fn a_read_only_file_is_refused_and_nothing_is_written() {
    use std::os::unix::fs::PermissionsExt;
    let d = dir("readonly");
    let keep = d.join("keep.svg");
    std::fs::write(&keep, "old").unwrap();
    std::fs::set_permissions(&keep, std::fs::Permissions::from_mode(0o444)).unwrap();
    let mut o = Outputs::default();
    o.add("table", &d.join("t.json"), "{}".into()).unwrap();
    o.add("svg", &keep, "<svg/>".into()).unwrap();
    let e = o.write().unwrap_err();
    assert_eq!(
        e.0,
        format!(
            "--svg must name a file it may write (got '{}': read-only, mode 0444; chmod u+w it, or name another)",
            keep.display()
        )
    );
    assert_eq!(std::fs::read_to_string(&keep).unwrap(), "old");
    assert_eq!(std::fs::metadata(&keep).unwrap().permissions().mode() & 0o777, 0o444);
    only(&d, &["keep.svg"]);
}

#[cfg(unix)]
#[test]
fn an_existing_file_is_written_through_keeping_its_links_owner_and_mode() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let d = dir("through");
    let f = d.join("f.svg");
    std::fs::write(&f, "old text, longer than the new").unwrap();
    std::fs::hard_link(&f, d.join("other-name.svg")).unwrap();
    std::fs::set_permissions(&f, std::fs::Permissions::from_mode(0o640)).unwrap();
    // as root: another owner, which a replaced file would lose
    let root = unsafe { libc::geteuid() } == 0;
    if root {
        std::os::unix::fs::chown(&f, Some(4321), Some(4321)).unwrap();
    }
    let before = std::fs::metadata(&f).unwrap();
    let mut o = Outputs::default();
    o.add("svg", &f, "<svg/>".into()).unwrap();
    o.write().unwrap();
    assert_eq!(std::fs::read_to_string(&f).unwrap(), "<svg/>");
    assert_eq!(std::fs::read_to_string(d.join("other-name.svg")).unwrap(), "<svg/>", "both links see the new text");
    let after = std::fs::metadata(&f).unwrap();
    assert_eq!(
        (after.ino(), after.nlink(), after.mode(), after.uid(), after.gid()),
        (before.ino(), 2, before.mode(), before.uid(), before.gid())
    );
    if root {
        assert_eq!(after.uid(), 4321);
    }
    only(&d, &["f.svg", "other-name.svg"]);
}

#[cfg(unix)]
#[test]
fn a_fifo_with_no_reader_times_out_naming_the_flag_and_writes_nothing() {
    let d = dir("fifo-alone");
    let fifo = d.join("pipe.svg");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    std::fs::write(d.join("t.json"), "old").unwrap();
    let mut o = Outputs::default();
    o.add("table", &d.join("t.json"), "new".into()).unwrap();
    o.add("svg", &fifo, "<svg/>".into()).unwrap();
    let e = o.write_within(std::time::Duration::from_millis(200)).unwrap_err();
    assert_eq!(e.0, format!("--svg could not write '{}': no reader opened the FIFO within 0.2 s", fifo.display()));
    assert_eq!(std::fs::read_to_string(d.join("t.json")).unwrap(), "old");
    only(&d, &["pipe.svg", "t.json"]);
}
