//! Why a serial port could not be opened, from the device's real owner, group and mode: the advice names the
//! group the device actually has (dialout on Debian and Ubuntu, uucp on Arch, ...), never a guessed one.

/// What `stat` says about a device, with the names of its owner and group, and whether this process is in
/// that group.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceAccess {
    /// The mode bits (`st_mode`), file type included.
    pub mode: u32,
    pub owner: String,
    pub group: String,
    /// This process has the device's group (real, effective or supplementary).
    pub in_group: bool,
}

/// `crw-rw----`, as `ls -l` writes the mode.
pub fn mode_text(mode: u32) -> String {
    let kind = match mode & 0o170_000 {
        0o020_000 => 'c',
        0o060_000 => 'b',
        0o040_000 => 'd',
        0o120_000 => 'l',
        0o010_000 => 'p',
        0o140_000 => 's',
        _ => '-',
    };
    let mut text = String::from(kind);
    for shift in [6, 3, 0] {
        let bits = (mode >> shift) & 0o7;
        text.push(if bits & 4 != 0 { 'r' } else { '-' });
        text.push(if bits & 2 != 0 { 'w' } else { '-' });
        text.push(if bits & 1 != 0 { 'x' } else { '-' });
    }
    text
}

/// The message for EACCES on `name`; `access` is None when the device could not even be looked at.
pub fn permission_denied_text(name: &str, access: Option<&DeviceAccess>) -> String {
    let Some(access) = access else {
        return format!("permission denied opening {name}: see who may open it with `ls -l {name}`");
    };
    let DeviceAccess { mode, owner, group, in_group } = access;
    let what = format!("permission denied opening {name} ({} {owner}:{group})", mode_text(*mode));
    let group_may = mode & 0o060 == 0o060;
    if group_may && *in_group {
        return format!(
            "{what}: this process is in the {group} group, which may open it, yet it was refused: an access \
             control list or a security module (AppArmor, SELinux) denies it; look with `getfacl {name}`"
        );
    }
    if group_may && group != "root" {
        return format!(
            "{what}: only {owner} and the {group} group may open it; add yourself to the group \
             (`sudo usermod -aG {group} $USER`, then log in again)"
        );
    }
    format!(
        "{what}: only {owner} may open it; give it a group with a udev rule (docs/troubleshooting.md, \
         Serial ports) or run as {owner}"
    )
}

/// Looks up `path`'s owner, group and mode, and whether this process is in its group.
#[cfg(unix)]
pub fn device_access(path: &std::path::Path) -> Option<DeviceAccess> {
    use std::os::unix::fs::MetadataExt;
    let metadata = std::fs::metadata(path).ok()?;
    let (uid, gid) = (metadata.uid(), metadata.gid());
    Some(DeviceAccess {
        mode: metadata.mode(),
        owner: name_of(uid, "/etc/passwd"),
        group: name_of(gid, "/etc/group"),
        in_group: process_groups().contains(&gid),
    })
}

/// Elsewhere there is no owner, group and mode to explain.
#[cfg(not(unix))]
pub fn device_access(_path: &std::path::Path) -> Option<DeviceAccess> {
    None
}

/// The name of `id` in a passwd or group file (name:x:id:...), else the number.
#[cfg(unix)]
fn name_of(id: u32, file: &str) -> String {
    let table = std::fs::read_to_string(file).unwrap_or_default();
    table
        .lines()
        .find_map(|line| {
            let mut fields = line.split(':');
            let name = fields.next()?;
            (fields.nth(1)?.parse::<u32>().ok()? == id).then(|| name.to_string())
        })
        .unwrap_or_else(|| id.to_string())
}

/// The group ids this process has: effective and supplementary.
#[cfg(unix)]
fn process_groups() -> Vec<u32> {
    // SAFETY: getegid has no preconditions and cannot fail.
    let mut groups = vec![unsafe { libc::getegid() }];
    // SAFETY: a null list with size 0 only asks for the count.
    let count = unsafe { libc::getgroups(0, std::ptr::null_mut()) };
    if let Ok(len @ 1..) = usize::try_from(count) {
        let mut list: Vec<libc::gid_t> = vec![0; len];
        // SAFETY: `list` holds `count` writable gid_t values.
        let filled = unsafe { libc::getgroups(count, list.as_mut_ptr()) };
        list.truncate(usize::try_from(filled).unwrap_or(0));
        groups.extend(list);
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(mode: u32, owner: &str, group: &str, in_group: bool) -> DeviceAccess {
        DeviceAccess { mode: 0o020_000 | mode, owner: owner.into(), group: group.into(), in_group }
    }

    #[test]
    fn the_mode_reads_as_ls_writes_it() {
        assert_eq!(mode_text(0o020_660), "crw-rw----");
        assert_eq!(mode_text(0o020_600), "crw-------");
        assert_eq!(mode_text(0o100_755), "-rwxr-xr-x");
    }

    #[test]
    fn dialout_is_suggested_only_for_a_dialout_device() {
        let text = permission_denied_text("/dev/ttyUSB0", Some(&device(0o660, "root", "dialout", false)));
        assert_eq!(
            text,
            "permission denied opening /dev/ttyUSB0 (crw-rw---- root:dialout): only root and the dialout group \
             may open it; add yourself to the group (`sudo usermod -aG dialout $USER`, then log in again)"
        );
        // Arch names the group uucp: that is the group to join.
        let text = permission_denied_text("/dev/ttyUSB0", Some(&device(0o660, "root", "uucp", false)));
        assert!(text.contains("(crw-rw---- root:uucp)"), "{text}");
        assert!(text.contains("`sudo usermod -aG uucp $USER`") && !text.contains("dialout"), "{text}");
    }

    #[test]
    fn a_device_closed_to_its_group_names_no_group_to_join() {
        for (mode, group) in [(0o600, "dialout"), (0o660, "root")] {
            let text = permission_denied_text("/dev/ttyS0", Some(&device(mode, "root", group, false)));
            assert!(text.contains("only root may open it; give it a group with a udev rule"), "{text}");
            assert!(!text.contains("usermod"), "{text}");
        }
    }

    #[test]
    fn a_member_of_the_group_is_told_something_else_denies_it() {
        let text = permission_denied_text("/dev/ttyACM0", Some(&device(0o660, "root", "dialout", true)));
        assert!(text.contains("this process is in the dialout group, which may open it, yet it was refused"));
        assert!(text.contains("`getfacl /dev/ttyACM0`") && !text.contains("usermod"), "{text}");
    }

    #[test]
    fn a_device_that_cannot_be_looked_at_says_how_to_look() {
        assert_eq!(
            permission_denied_text("/dev/x", None),
            "permission denied opening /dev/x: see who may open it with `ls -l /dev/x`"
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_real_file_is_read_with_its_mode_and_names() {
        use std::os::unix::fs::PermissionsExt;
        let file = tempfile::NamedTempFile::new().unwrap();
        std::fs::set_permissions(file.path(), std::fs::Permissions::from_mode(0o640)).unwrap();
        let access = device_access(file.path()).unwrap();
        assert_eq!(mode_text(access.mode), "-rw-r-----");
        // The file is ours, so its group is our effective group.
        assert!(access.in_group);
        // SAFETY: geteuid has no preconditions.
        let uid = unsafe { libc::geteuid() };
        assert_eq!(access.owner, name_of(uid, "/etc/passwd"));
        assert_eq!(name_of(0, "/etc/passwd"), "root");
        assert_eq!(name_of(4_000_000_000, "/etc/group"), "4000000000");
    }
}
