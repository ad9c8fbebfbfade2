#!/bin/sh
# Runs inside the VM as a systemd oneshot (vm-scenario.service), as root: enables tracerctl-record@ instances
# with systemctl and checks what systemd made of the unit. One "CHECK name: PASS|FAIL" line per check, then
# SCENARIO PASS or SCENARIO FAIL; the evidence follows a failed check, each line prefixed "  | ".
export PATH=/usr/sbin:/usr/bin:/sbin:/bin
pass=0 fail=0 failed=""
check() { # name, condition (a command), evidence (a command)
    if sh -c "$2" >/dev/null 2>&1; then
        echo "CHECK $1: PASS"
        pass=$((pass + 1))
    else
        echo "CHECK $1: FAIL"
        sh -c "$3" 2>&1 | sed 's/^/  | /'
        fail=$((fail + 1))
        failed="$failed $1"
    fi
}
wait_for() { # condition, tenths of a second
    n=0
    while [ $n -lt "$2" ]; do
        sh -c "$1" >/dev/null 2>&1 && return 0
        sleep 0.1
        n=$((n + 1))
    done
    return 1
}
main_pid() { systemctl show -p MainPID --value "$1"; }
# the files that the unit's processes (all of its cgroup) hold open
unit_fds() {
    while read -r p; do
        ls -l "/proc/$p/fd" 2>/dev/null
    done <"/sys/fs/cgroup$(systemctl show -p ControlGroup --value "$1")/cgroup.procs"
}
echo "SCENARIO START: systemd $(systemctl --version | head -n 1 | cut -d' ' -f2), recorder: $(cat /etc/recorder-kind)"
: >/tmp/host-marker

u=tracerctl-record@vcan0.service
systemctl enable --now "$u" 2>&1 | sed 's/^/  enable: /'
wait_for "systemctl is-active --quiet $u" 100
check service_enabled_and_active "systemctl is-enabled --quiet $u && systemctl is-active --quiet $u" \
    "systemctl status --no-pager $u; journalctl --no-pager -u $u"
pid=$(main_pid "$u")
check service_unprivileged_in_dialout \
    "grep -q '^Uid:[[:space:]]*$(id -u tracerctl)[[:space:]]' /proc/$pid/status && grep -qw 20 /proc/$pid/status && grep -q '^CapEff:[[:space:]]*0*\$' /proc/$pid/status" \
    "cat /proc/$pid/status; id tracerctl"
check service_state_directory "[ \"\$(stat -c %U:%G:%a /var/lib/tracerctl/vcan0)\" = tracerctl:tracerctl:755 ] && [ \"\$(stat -c %U /var/lib/tracerctl)\" = root ]" \
    "ls -la /var/lib/tracerctl /var/lib/tracerctl/vcan0"

for i in 1 2 3 4 5; do cansend vcan0 "12$i#0$i"; done
if [ "$(cat /etc/recorder-kind)" = stand-in ]; then
    wait_for "[ \$(grep -c '^(' /var/lib/tracerctl/vcan0/frames.log) -ge 5 ]" 50
    check service_can_frames_recorded "[ \$(grep -c ' vcan0 12[1-5]#0[1-5]\$' /var/lib/tracerctl/vcan0/frames.log) = 5 ]" \
        "cat /var/lib/tracerctl/vcan0/frames.log"
    check service_sandbox "[ \"\$(cat /var/lib/tracerctl/vcan0/sandbox | tr '\n' ,)\" = 'state dir writable,etc read-only,home hidden,tmp private,' ]" \
        "cat /var/lib/tracerctl/vcan0/sandbox"
else
    sleep 2
    check service_record_status "tracerctl record --status --dir /var/lib/tracerctl/vcan0" \
        "tracerctl record --status --dir /var/lib/tracerctl/vcan0; ls -laR /var/lib/tracerctl/vcan0"
fi
check service_logs_to_journal "[ -n \"\$(journalctl --no-pager -o cat -u $u _UID=$(id -u tracerctl))\" ]" \
    "journalctl --no-pager -o verbose -u $u | tail -n 40"
systemctl stop "$u"
check service_stops_with_exit_0 "[ \"\$(systemctl show -p Result --value $u)\" = success ] && [ \"\$(systemctl show -p ExecMainStatus --value $u)\" = 0 ]" \
    "systemctl show -p Result,ExecMainStatus,ExecMainCode $u; journalctl --no-pager -u $u | tail -n 20"

# A serial port owned by root:dialout 0660 (what udev makes of /dev/ttyS*): the recorder reaches it through the
# dialout group alone.
s=tracerctl-record@dev-ttyS2.service
systemctl start "$s"
n=0
while [ $n -lt 100 ] && ! unit_fds "$s" | grep -q /dev/ttyS2; do sleep 0.1; n=$((n + 1)); done
check service_serial_port_open "[ $n -lt 100 ]" "ls -l /dev/ttyS2; unit_fds $s; journalctl --no-pager -u $s"
systemctl stop "$s"

# An adapter missing at start: the unit starts all the same and is not restarted; the recorder waits.
m=tracerctl-record@vcan9.service
systemctl start "$m"
sleep 3
check service_missing_adapter_waited_for "systemctl is-active --quiet $m && [ \"\$(systemctl show -p NRestarts --value $m)\" = 0 ]" \
    "systemctl status --no-pager $m; journalctl --no-pager -u $m"
ip link add dev vcan9 type vcan && ip link set up vcan9
sleep 1
cansend vcan9 321#AA
sleep 1
if [ "$(cat /etc/recorder-kind)" = stand-in ]; then
    check service_adapter_plugged_in_later "grep -q ' vcan9 321#AA\$' /var/lib/tracerctl/vcan9/frames.log" \
        "ls -la /var/lib/tracerctl/vcan9; journalctl --no-pager -u $m"
fi
systemctl stop "$m"

# What a path with '-' in it becomes (systemd-escape --path /dev/serial/by-id/usb-X-port0): shown, not checked.
mkdir -p /dev/serial/by-id && ln -sf ../../ttyS3 /dev/serial/by-id/usb-X-port0
e=$(systemd-escape --path --template=tracerctl-record@.service /dev/serial/by-id/usb-X-port0)
systemctl start "$e"
sleep 2
echo "INFO escaped instance $e: the recorder said: $(journalctl --no-pager -o cat -u "$e" _UID="$(id -u tracerctl)" | head -n 3 | tr '\n' ' ')"
echo "INFO escaped instance $e: state dirs: $(cd /var/lib/tracerctl && echo *)"
systemctl stop "$e"

echo "SCENARIO END: $pass passed, $fail failed"
if [ $fail -eq 0 ]; then echo "SCENARIO PASS"; else echo "SCENARIO FAIL:$failed"; fi
# poweroff.target as a job: `systemctl poweroff` asks logind over D-Bus, which this VM has not
systemctl --no-block start poweroff.target
