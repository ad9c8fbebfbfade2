# Print an optspec for argparse to handle cmd's options that are independent of any subcommand.
function __fish_tracerctl_global_optspecs
    string join \n protocol= color= profile= iface= serial= baud= sim fault= sim-param= replay= speed= h/help V/version
end

function __fish_tracerctl_needs_command
    # Figure out if the current invocation already has a command.
    set -l cmd (commandline -opc)
    set -e cmd[1]
    argparse -s (__fish_tracerctl_global_optspecs) -- $cmd 2>/dev/null
    or return
    if set -q argv[1]
        # Also print the command, so this can be used to figure out what it is.
        echo $argv[1]
        return 1
    end
    return 0
end

function __fish_tracerctl_using_subcommand
    set -l cmd (__fish_tracerctl_needs_command)
    test -z "$cmd"
    and return 1
    contains -- $cmd[1] $argv
end

complete -c tracerctl -n "__fish_tracerctl_needs_command" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "decode" -d 'Decode candump logs, single frames or RS232 captures'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "monitor" -d 'Watch the live bus, decoded, with warnings when periodic frames go stale'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "drive" -d 'Drive at a fixed speed: 50 Hz commands, ramped and capped; Ctrl-C stops it'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "commission" -d 'Acceptance test drive: measure how the robot answers, PASS/WARN/FAIL per figure'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "doctor" -d 'Why isn\'t it moving? Check the link, bus, protocol, mode, E-stop, faults and battery (PASS/WARN/FAIL)'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "mode" -d 'Switch the control mode (0x421) and report it before and after'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "clear-errors" -d 'Clear latched faults (0x441) and report which bits cleared and which remain'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "lights" -d 'Set the lights (0x121), confirmed from the light state (0x231)'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "send-raw" -d 'Show what raw frames mean, then send them (cansend syntax, or hex RS232 frames)'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "sim" -d 'Run a virtual TRACER on a CAN interface (e.g. --iface vcan0) or a new pseudo-terminal (--pty)'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "dashboard" -d 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "dash" -d 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "record" -d 'Black box: record the bus unattended, keep the minutes around each fault as an incident; never sends'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "report" -d 'Make the support bundle for the vendor: doctor, firmware version, rates, incidents, host facts'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "completions" -d 'Print a shell completion script to standard output'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "config" -d 'The configuration files: every effective setting with its source (show), the files read (path)'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s f -l format -d 'Output format [default: text, or mcap for -o FILE.mcap]. MCAP (Foxglove, PlotJuggler) needs -o FILE and is written by one thread' -r -f -a "text\t'One readable line per frame'
json\t'One JSON object per line (schema in docs/json.md)'
csv\t'Comma-separated values with a fixed header (for spreadsheets)'
mcap\t'An MCAP file for Foxglove and PlotJuggler (docs/foxglove.md); needs -o FILE'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s o -l output -d 'Write the output to FILE instead of standard output (a .mcap name means --format mcap)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l mcap-compression -d 'Chunk compression of MCAP output' -r -f -a "zstd\t''
lz4\t''
none\t''"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l id -d 'Only frames with these identifiers (hex, comma-separated: 0x211,221, or AA01 for serial)' -r -f
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l msg -d 'Only these messages (comma-separated), e.g. system_state,odometry; also raw, invalid, error_frame' -r -f -a "motion_command\t''
light_command\t''
control_mode_command\t''
fault_clear\t''
version_request\t''
system_state\t''
motion_state\t''
light_state\t''
rc_state\t''
motor_high_speed\t''
motor_low_speed\t''
odometry\t''
version_response\t''
raw\t''
invalid\t''
error_frame\t''
remote_request\t''"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l plot -d 'Draw battery voltage, commanded vs measured speeds, motor RPM and current, with fault and E-stop events marked, as an SVG file' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s j -l threads -d 'Threads for text logs (candump, Vector ASC, PEAK trc): files and standard input, plain or compressed, in every mode (--summary, --plot, --delta-stamps too; default: all cores; 1: one)' -r -f
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s s -l summary -d 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l strict -d 'Stop at the first bad line, bad frame or corrupted serial frame (exit status 3)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l delta-stamps -d 'Console timestamps are deltas between frames (candump -t d): add them up. Such stamps look exactly like those of candump -t z, so tracerctl cannot tell them apart'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l no-progress -d 'Never show a progress bar (shown only for large files, on a terminal)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l no-mmap -d 'Read files with positioned reads only, never mapped into memory (also TRACERCTL_NO_MMAP=1); the output is the same'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -s f -l format -d 'Output format' -r -f -a "text\t'One readable line per frame'
json\t'One JSON object per line (schema in docs/json.md)'
csv\t'Comma-separated values with a fixed header (for spreadsheets)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l id -d 'Only frames with these identifiers (comma-separated hex numbers)' -r -f
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l msg -d 'Only these messages, e.g. system_state,odometry (see --help for all)' -r -f -a "motion_command\t''
light_command\t''
control_mode_command\t''
fault_clear\t''
version_request\t''
system_state\t''
motion_state\t''
light_state\t''
rc_state\t''
motor_high_speed\t''
motor_low_speed\t''
odometry\t''
version_response\t''
raw\t''
invalid\t''
error_frame\t''
remote_request\t''"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l log -d 'Also write every frame to FILE in candump -L format (replayable with canplayer), flushed per line; a .mcap name writes MCAP instead (docs/foxglove.md), flushed every second' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l duration -d 'Stop after this long (e.g. 10s; up to 30 days); default: until Ctrl-C' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l silence -d 'Warn when the bus is silent this long (0 to 1h; 0: never)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -s t -l timestamp -d 'Time column of text lines, as candump -t: a, d, z or A (default: absolute)' -r -f -a "absolute\t'(a) seconds since the epoch, 6 decimals (9 when the link stamps nanoseconds)'
delta\t'(d) seconds since the previous line shown (000.020000); the first line is 0'
zero\t'(z) seconds since the first line shown (000.000000 first)'
date\t'(A) local date and time (2023-11-14 22:13:20.000250)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -s n -l count -d 'Exit after COUNT frames shown (as candump -n), with the summary; exit status 0' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l raw -d 'Print frames as candump -L lines, undecoded (so not with --format)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l no-data -d 'Leave the raw bytes out of text lines (the line decode prints, for scripts that parse it)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand monitor" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l linear -d 'Linear speed in m/s (+ forward; -100 to 100, capped at --max-linear); 0 when only --angular is given' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l angular -d 'Angular speed in rad/s (+ turns counter-clockwise; -100 to 100, capped at --max-angular); 0 when only --linear is given' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l for -l duration -d 'How long to drive (e.g. 2s, 1500ms; up to 24h); default: until Ctrl-C' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l max-linear -d 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l max-angular -d 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l accel -d 'Linear acceleration of the ramp, m/s²' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l angular-accel -d 'Angular acceleration of the ramp, rad/s²' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l decel -d 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l angular-decel -d 'Angular braking, rad/s²; at least --angular-accel' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -s f -l format -d 'Status lines and final report on stdout: text, or JSON (docs/json.md)' -r -f -a "text\t'Lines for people'
json\t'JSON (docs/json.md)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l record -d 'Record the frames received and sent to FILE (candump log; MCAP for a .mcap name)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l ignore-faults -d 'Start even with the E-stop pressed or a latched fault (the robot may still refuse)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand drive" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l max-linear -d 'Cap on the linear speed of the steps, m/s (at most 0.6 is used: the 1 m straight must hold a step)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l max-angular -d 'Cap on the angular speed of the spins, rad/s (at most 0.7853 is used)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l include -d 'Add an opt-in step (repeatable)' -r -f -a "timeout\t'The command-timeout probe: nothing is sent for 1.5 s at 0.1 m/s; the robot must stop by itself'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l record -d 'Write a candump log of the run (frames received and sent) to FILE; a .mcap name writes MCAP' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -s f -l format -d 'The report on stdout: text, or one JSON object (docs/commission.md)' -r -f -a "text\t'Lines for people'
json\t'JSON (docs/json.md)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l plot -d 'Draw each step (commanded, measured and wheel speeds) into FILE.svg' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l save -d 'Keep the JSON record as DIR/<link>-<UTC time>.json (never overwriting)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l compare -d 'After the run, show each figure\'s old and new value and flag what drifted since OLD.json' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l yes -d 'Drive without asking on the terminal (the operator has checked the free space)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l dry-run -d 'Print the steps, the bounds and the duration, and exit: no link opened, nothing sent'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand commission" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l listen -d 'How long to listen to the robot (100ms to 10m)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -s f -l format -d 'Format of the report' -r -f -a "text\t'Lines for people'
json\t'JSON (docs/json.md)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l probe -d 'Also check that the robot accepts commands: control mode and zero-velocity motion (it does not move)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand doctor" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l timeout -d 'How long to wait for the robot to confirm (0 to 10m)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand mode" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l timeout -d 'How long to watch the status afterwards (0 to 10m)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand clear-errors" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l front -d 'Front light mode' -r -f -a "off\t''
on\t''
breath\t''
custom\t''"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l brightness -d 'Front brightness for --front custom, percent (0-100)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l rear -d 'Rear light mode (reserved on TRACER: the firmware ignores it)' -r -f -a "off\t''
on\t''
breath\t''
custom\t''"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l rear-brightness -d 'Rear brightness for --rear custom, percent (0-100)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l timeout -d 'How long to wait for the light state to confirm (0 to 10m)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l release -d 'Hand the lights back to the firmware'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand lights" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l repeat -d 'Send the frames this many times' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l period -d 'Time between repeats, milliseconds' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -s f -l format -d 'What was sent, on stdout, as text or JSON (docs/json.md); diagnostics go to stderr' -r -f -a "text\t'Lines for people'
json\t'JSON (docs/json.md)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l force -d 'Allow frames that can move the robot (0x111, 0x130, 0x421, RS232 motion control), and frames the robot would reject (a TRACER identifier with the wrong length or checksum)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l fix-checksum -d 'Compute RS232 checksums instead of requiring them'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand send-raw" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l rc -d 'An RC transmitter is on, with SWB in this position (middle = RC mode overrides commands)' -r -f -a "top\t'SWB at the top: command mode allowed'
middle\t'SWB in the middle: RC mode, commands are ignored'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l battery -d 'Starting battery voltage (18 to 30)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l drain -d 'Speed up battery drain by this factor (to see the low-battery warnings quickly; 0 to 1000000)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l duration -d 'Stop after this long (at most 30 days); default: until Ctrl-C' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l pty -d 'Serve on a new pseudo-terminal (prints its path) instead of a CAN interface or --serial port'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand sim" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l max-linear -d 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l max-angular -d 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l accel -d 'Linear acceleration of the ramp, m/s²' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l angular-accel -d 'Angular acceleration of the ramp, rad/s²' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l decel -d 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l angular-decel -d 'Angular braking, rad/s²; at least --angular-accel' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l record -d 'Write a candump log of the session (frames received and sent) to FILE; a .mcap name writes MCAP (Foxglove, PlotJuggler: docs/foxglove.md)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l key-timeout -d 'Without key-release events (tmux, most terminals over SSH): a held key counts as released when no auto-repeat came for DURATION (20ms to 1.25s), instead of the deadline learned from the key stream. Longer rides out a jittery link, shorter stops sooner' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l watch -d 'Watch only: never arm driving, never send anything (for a robot that ROS or an RC transmitter drives)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dashboard" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l max-linear -d 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l max-angular -d 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l accel -d 'Linear acceleration of the ramp, m/s²' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l angular-accel -d 'Angular acceleration of the ramp, rad/s²' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l decel -d 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l angular-decel -d 'Angular braking, rad/s²; at least --angular-accel' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l record -d 'Write a candump log of the session (frames received and sent) to FILE; a .mcap name writes MCAP (Foxglove, PlotJuggler: docs/foxglove.md)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l key-timeout -d 'Without key-release events (tmux, most terminals over SSH): a held key counts as released when no auto-repeat came for DURATION (20ms to 1.25s), instead of the deadline learned from the key stream. Longer rides out a jittery link, shorter stops sooner' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l watch -d 'Watch only: never arm driving, never send anything (for a robot that ROS or an RC transmitter drives)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand dash" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l dir -d 'The recorder directory [default: $XDG_STATE_HOME/tracerctl/record, or for --status, --list and --mark the one recorder directory under /var/lib/tracerctl when there is only one]' -r -f -a "(__fish_complete_directories)"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l segment -d 'A new segment this often (1s to 1d)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l max-total -d 'The ring\'s size, e.g. 1GiB, 500MB (at least 1 MiB)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l max-age -d 'Segments older than this are removed (1m to 366d)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l before -d 'An incident keeps the frames from this long before its trigger, from 0 to 1h' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l after -d '... to this long after it (0 to 1h); a trigger inside the window extends it' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l max-incidents -d 'Incidents kept, the oldest removed first' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l trigger -d 'Also a trigger (repeatable): a decoded field and a value, e.g. \'battery_voltage<23.0\' or \'id=0x441\'' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l instance -d 'The link from a systemd instance name: a profile, can0 (SocketCAN), or ttyUSB0, dev/ttyUSB0 (serial)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -s f -l format -d 'Output format of --status and --list' -r -f -a "text\t'Lines for people'
json\t'JSON (docs/json.md)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l no-default-triggers -d 'Only the --trigger expressions and marks, not the default triggers'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l dry-run -d 'Print the link, directory and settings it would record with, and exit without opening the link'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l status -d 'Is a recorder running in DIR: since when, frames recorded and lost, the ring, the last incidents'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l list -d 'The incidents in DIR, oldest first'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l mark -d 'Leave a mark (with NOTE): the running recorder keeps an incident around now'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand record" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -s o -l output -d 'The bundle\'s file, or a directory to write the default name in [default: tracerctl-report-HOST-TIME.tar.gz here]' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l dir -d 'The recorder\'s directory [default: /var/lib/tracerctl/record, if there is one]' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l listen -d 'How long to listen to the robot (100ms to 10m); its frames are kept when no recorder runs' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l max-size -d 'The cap on the bundle\'s size: 50MB, 500kB, 1GiB (kB, MB, GB are powers of 1000; KiB, MiB, GiB of 1024)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l incidents -d 'How many incidents to take, newest first' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l ring-minutes -d 'How many minutes of the recorder\'s ring to take (its last ones)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l force -d 'Replace an existing file of that name'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l probe -d 'Also run the doctor\'s probe: it sends a mode command and zero-velocity motion, never moving the robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand report" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -f -a "show" -d 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -f -a "path" -d 'The configuration files looked for, in order, and which exist (reads none of them)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and not __fish_seen_subcommand_from show path help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -s f -l format -d 'Text, or JSON (docs/json.md)' -r -f -a "text\t'Lines for people'
json\t'JSON (docs/json.md)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from show" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l color -d 'When to colour output (an explicit always or never overrides NO_COLOR)' -r -f -a "auto\t'Colour on a terminal, unless the NO_COLOR environment variable is set'
always\t'Colour even into a pipe or a file, even with NO_COLOR set'
never\t'Never colour'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l profile -d 'Settings of this robot\'s profile in the configuration files ([profiles.NAME]; tracerctl config show)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l iface -d 'CAN interface [default: $TRACERCTL_IFACE or can0]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l serial -d 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l baud -d 'Serial baud rate (with --serial) [default: 115200]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l fault -d 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)' -r -f -a "estop\t'press the E-stop: stops at once, commands ignored'
estop-release\t'release the E-stop: standby until command mode again'
motor1-overheat\t'driver 1 at 70 C: over-temperature protection latches'
motor2-overheat\t'driver 2 at 70 C: over-temperature protection latches'
overcurrent\t'over-current protection latches on both drivers'
motor1-overcurrent\t'over-current protection latches on driver 1'
motor2-overcurrent\t'over-current protection latches on driver 2'
motor1-comm\t'driver 1 communication lost: latches until cleared'
motor2-comm\t'driver 2 communication lost: latches until cleared'
battery-warning\t'battery to 22.4 V: under-voltage warning'
battery-low\t'battery to 21.9 V: under-voltage; heavy loads cut off'
battery-empty\t'battery to 21.4 V: cut off until battery-ok'
battery-ok\t'fresh battery at the start voltage'
rc-lost\t'RC transmitter link lost: motion stops'
rc-restore\t'RC transmitter link back'
swb-middle\t'SWB to the middle: RC mode, host commands ignored'
swb-top\t'RC switch SWB to the top: command mode allowed'
other-host\t'another host takes the mode (CAN vs RS232) for 200 ms'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l sim-param -d 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)' -r -f -a "dead-time=\t'delay from a target change to the drive acting on it'
lag=\t'first-order lag of actual speeds behind the ramp (0: none)'
max-accel=\t'linear accel. and braking limit; angular: 2 x this, rad/s2'
left-gain=\t'left wheel\'s actual speed / its command (tyre wear, motor)'
right-gain=\t'right wheel\'s actual speed / its command'
track-width=\t'effective track the body turns with (firmware: 0.36 m)'
odometer-scale=\t'the odometers report this x the true wheel distance'
command-timeout=\t'target drops to 0 this long after the last command came'
battery-ocv=\t'open-circuit battery voltage at the start'
battery-r=\t'battery internal resistance: voltage sag = current x this'
noise=\t'std dev of noise on reported values, in each field\'s quanta'
seed=\t'noise generator seed: the same seed gives the same frames'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l replay -d 'Play back a candump log as a read-only source (for monitor, dashboard)' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l speed -d 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -l sim -d 'Drive an in-process virtual TRACER, not a robot'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from path" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from help" -f -a "show" -d 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from help" -f -a "path" -d 'The configuration files looked for, in order, and which exist (reads none of them)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand config; and __fish_seen_subcommand_from help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "decode" -d 'Decode candump logs, single frames or RS232 captures'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "monitor" -d 'Watch the live bus, decoded, with warnings when periodic frames go stale'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "drive" -d 'Drive at a fixed speed: 50 Hz commands, ramped and capped; Ctrl-C stops it'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "commission" -d 'Acceptance test drive: measure how the robot answers, PASS/WARN/FAIL per figure'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "doctor" -d 'Why isn\'t it moving? Check the link, bus, protocol, mode, E-stop, faults and battery (PASS/WARN/FAIL)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "mode" -d 'Switch the control mode (0x421) and report it before and after'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "clear-errors" -d 'Clear latched faults (0x441) and report which bits cleared and which remain'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "lights" -d 'Set the lights (0x121), confirmed from the light state (0x231)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "send-raw" -d 'Show what raw frames mean, then send them (cansend syntax, or hex RS232 frames)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "sim" -d 'Run a virtual TRACER on a CAN interface (e.g. --iface vcan0) or a new pseudo-terminal (--pty)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "dashboard" -d 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "record" -d 'Black box: record the bus unattended, keep the minutes around each fault as an incident; never sends'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "report" -d 'Make the support bundle for the vendor: doctor, firmware version, rates, incidents, host facts'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "completions" -d 'Print a shell completion script to standard output'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "config" -d 'The configuration files: every effective setting with its source (show), the files read (path)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode monitor drive commission doctor mode clear-errors lights send-raw sim dashboard record report completions config help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and __fish_seen_subcommand_from config" -f -a "show" -d 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and __fish_seen_subcommand_from config" -f -a "path" -d 'The configuration files looked for, in order, and which exist (reads none of them)'
