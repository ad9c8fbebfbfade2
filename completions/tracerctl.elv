
use builtin;
use str;

set edit:completion:arg-completer[tracerctl] = {|@words|
    fn spaces {|n|
        builtin:repeat $n ' ' | str:join ''
    }
    fn cand {|text desc|
        edit:complex-candidate $text &display=$text' '(spaces (- 14 (wcswidth $text)))$desc
    }
    var command = 'tracerctl'
    for word $words[1..-1] {
        if (str:has-prefix $word '-') {
            break
        }
        set command = $command';'$word
    }
    var completions = [
        &'tracerctl'= {
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand decode 'Decode candump logs, single frames or RS232 captures'
            cand monitor 'Watch the live bus, decoded, with warnings when periodic frames go stale'
            cand drive 'Drive at a fixed speed: 50 Hz commands, ramped and capped; Ctrl-C stops it'
            cand doctor 'Why isn''t it moving? Check the link, bus, protocol, mode, E-stop, faults and battery (PASS/WARN/FAIL)'
            cand mode 'Switch the control mode (0x421) and report it before and after'
            cand clear-errors 'Clear latched faults (0x441) and report which bits cleared and which remain'
            cand lights 'Set the lights (0x121), confirmed from the light state (0x231)'
            cand send-raw 'Show what raw frames mean, then send them (cansend syntax, or hex RS232 frames)'
            cand sim 'Run a virtual TRACER on a CAN interface (e.g. --iface vcan0) or a new pseudo-terminal (--pty)'
            cand dashboard 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive'
            cand dash 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive'
            cand record 'Black box: record the bus unattended, keep the minutes around each fault as an incident; never sends'
            cand report 'Make the support bundle for the vendor: doctor, firmware version, rates, incidents, host facts'
            cand completions 'Print a shell completion script to standard output'
            cand config 'The configuration files: every effective setting with its source (show), the files read (path)'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'tracerctl;decode'= {
            cand -f 'Output format [default: text, or mcap for -o FILE.mcap]. MCAP (Foxglove, PlotJuggler) needs -o FILE and is written by one thread'
            cand --format 'Output format [default: text, or mcap for -o FILE.mcap]. MCAP (Foxglove, PlotJuggler) needs -o FILE and is written by one thread'
            cand -o 'Write the output to FILE instead of standard output (a .mcap name means --format mcap)'
            cand --output 'Write the output to FILE instead of standard output (a .mcap name means --format mcap)'
            cand --mcap-compression 'Chunk compression of MCAP output'
            cand --id 'Only frames with these identifiers (hex, comma-separated: 0x211,221, or AA01 for serial)'
            cand --msg 'Only these messages (comma-separated), e.g. system_state,odometry; also raw, invalid, error_frame'
            cand --plot 'Draw battery voltage, commanded vs measured speeds, motor RPM and current, with fault and E-stop events marked, as an SVG file'
            cand -j 'Threads for text logs (candump, Vector ASC, PEAK trc): files and standard input, plain or compressed, in every mode (--summary, --plot, --delta-stamps too; default: all cores; 1: one)'
            cand --threads 'Threads for text logs (candump, Vector ASC, PEAK trc): files and standard input, plain or compressed, in every mode (--summary, --plot, --delta-stamps too; default: all cores; 1: one)'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand -s 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance'
            cand --summary 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance'
            cand --strict 'Stop at the first bad line, bad frame or corrupted serial frame (exit status 3)'
            cand --delta-stamps 'Console timestamps are deltas between frames (candump -t d): add them up. Such stamps look exactly like those of candump -t z, so tracerctl cannot tell them apart'
            cand --no-progress 'Never show a progress bar (shown only for large files, on a terminal)'
            cand --no-mmap 'Read files with positioned reads only, never mapped into memory (also TRACERCTL_NO_MMAP=1); the output is the same'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;monitor'= {
            cand -f 'Output format'
            cand --format 'Output format'
            cand --id 'Only frames with these identifiers (comma-separated hex numbers)'
            cand --msg 'Only these messages, e.g. system_state,odometry (see --help for all)'
            cand --log 'Also write every frame to FILE in candump -L format (replayable with canplayer), flushed per line; a .mcap name writes MCAP instead (docs/foxglove.md), flushed every second'
            cand --duration 'Stop after this long (e.g. 10s; up to 30 days); default: until Ctrl-C'
            cand --silence 'Warn when the bus is silent this long (0 to 1h; 0: never)'
            cand -t 'Time column of text lines, as candump -t: a, d, z or A (default: absolute)'
            cand --timestamp 'Time column of text lines, as candump -t: a, d, z or A (default: absolute)'
            cand -n 'Exit after COUNT frames shown (as candump -n), with the summary; exit status 0'
            cand --count 'Exit after COUNT frames shown (as candump -n), with the summary; exit status 0'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --raw 'Print frames as candump -L lines, undecoded (so not with --format)'
            cand --no-data 'Leave the raw bytes out of text lines (the line decode prints, for scripts that parse it)'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;drive'= {
            cand --linear 'Linear speed in m/s (+ forward; -100 to 100, capped at --max-linear); 0 when only --angular is given'
            cand --angular 'Angular speed in rad/s (+ turns counter-clockwise; -100 to 100, capped at --max-angular); 0 when only --linear is given'
            cand --for 'How long to drive (e.g. 2s, 1500ms; up to 24h); default: until Ctrl-C'
            cand --duration 'How long to drive (e.g. 2s, 1500ms; up to 24h); default: until Ctrl-C'
            cand --max-linear 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)'
            cand --max-angular 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)'
            cand --accel 'Linear acceleration of the ramp, m/s²'
            cand --angular-accel 'Angular acceleration of the ramp, rad/s²'
            cand --decel 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s'
            cand --angular-decel 'Angular braking, rad/s²; at least --angular-accel'
            cand -f 'Status lines and final report on stdout: text, or JSON (docs/json.md)'
            cand --format 'Status lines and final report on stdout: text, or JSON (docs/json.md)'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --ignore-faults 'Start even with the E-stop pressed or a latched fault (the robot may still refuse)'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;doctor'= {
            cand --listen 'How long to listen to the robot (100ms to 10m)'
            cand -f 'Format of the report'
            cand --format 'Format of the report'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --probe 'Also check that the robot accepts commands: control mode and zero-velocity motion (it does not move)'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;mode'= {
            cand --timeout 'How long to wait for the robot to confirm (0 to 10m)'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;clear-errors'= {
            cand --timeout 'How long to watch the status afterwards (0 to 10m)'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;lights'= {
            cand --front 'Front light mode'
            cand --brightness 'Front brightness for --front custom, percent (0-100)'
            cand --rear 'Rear light mode (reserved on TRACER: the firmware ignores it)'
            cand --rear-brightness 'Rear brightness for --rear custom, percent (0-100)'
            cand --timeout 'How long to wait for the light state to confirm (0 to 10m)'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --release 'Hand the lights back to the firmware'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;send-raw'= {
            cand --repeat 'Send the frames this many times'
            cand --period 'Time between repeats, milliseconds'
            cand -f 'What was sent, on stdout, as text or JSON (docs/json.md); diagnostics go to stderr'
            cand --format 'What was sent, on stdout, as text or JSON (docs/json.md); diagnostics go to stderr'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --force 'Allow frames that can move the robot (0x111, 0x130, 0x421, RS232 motion control), and frames the robot would reject (a TRACER identifier with the wrong length or checksum)'
            cand --fix-checksum 'Compute RS232 checksums instead of requiring them'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;sim'= {
            cand --rc 'An RC transmitter is on, with SWB in this position (middle = RC mode overrides commands)'
            cand --battery 'Starting battery voltage (18 to 30)'
            cand --drain 'Speed up battery drain by this factor (to see the low-battery warnings quickly; 0 to 1000000)'
            cand --duration 'Stop after this long (at most 30 days); default: until Ctrl-C'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --pty 'Serve on a new pseudo-terminal (prints its path) instead of a CAN interface or --serial port'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;dashboard'= {
            cand --max-linear 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)'
            cand --max-angular 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)'
            cand --accel 'Linear acceleration of the ramp, m/s²'
            cand --angular-accel 'Angular acceleration of the ramp, rad/s²'
            cand --decel 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s'
            cand --angular-decel 'Angular braking, rad/s²; at least --angular-accel'
            cand --record 'Write a candump log of the session (frames received and sent) to FILE; a .mcap name writes MCAP (Foxglove, PlotJuggler: docs/foxglove.md)'
            cand --key-timeout 'Without key-release events (tmux, most terminals over SSH): a held key counts as released when no auto-repeat came for DURATION (20ms to 1.25s), instead of the deadline learned from the key stream. Longer rides out a jittery link, shorter stops sooner'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --watch 'Watch only: never arm driving, never send anything (for a robot that ROS or an RC transmitter drives)'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;dash'= {
            cand --max-linear 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)'
            cand --max-angular 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)'
            cand --accel 'Linear acceleration of the ramp, m/s²'
            cand --angular-accel 'Angular acceleration of the ramp, rad/s²'
            cand --decel 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s'
            cand --angular-decel 'Angular braking, rad/s²; at least --angular-accel'
            cand --record 'Write a candump log of the session (frames received and sent) to FILE; a .mcap name writes MCAP (Foxglove, PlotJuggler: docs/foxglove.md)'
            cand --key-timeout 'Without key-release events (tmux, most terminals over SSH): a held key counts as released when no auto-repeat came for DURATION (20ms to 1.25s), instead of the deadline learned from the key stream. Longer rides out a jittery link, shorter stops sooner'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --watch 'Watch only: never arm driving, never send anything (for a robot that ROS or an RC transmitter drives)'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;record'= {
            cand --dir 'The recorder directory [default: $XDG_STATE_HOME/tracerctl/record, or for --status, --list and --mark the one recorder directory under /var/lib/tracerctl when there is only one]'
            cand --segment 'A new segment this often (1s to 1d)'
            cand --max-total 'The ring''s size, e.g. 1GiB, 500MB (at least 1 MiB)'
            cand --max-age 'Segments older than this are removed (1m to 366d)'
            cand --before 'An incident keeps the frames from this long before its trigger, from 0 to 1h'
            cand --after '... to this long after it (0 to 1h); a trigger inside the window extends it'
            cand --max-incidents 'Incidents kept, the oldest removed first'
            cand --trigger 'Also a trigger (repeatable): a decoded field and a value, e.g. ''battery_voltage<23.0'' or ''id=0x441'''
            cand --instance 'The link from a systemd instance name: a profile, can0 (SocketCAN), or ttyUSB0, dev/ttyUSB0 (serial)'
            cand -f 'Output format of --status and --list'
            cand --format 'Output format of --status and --list'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --no-default-triggers 'Only the --trigger expressions and marks, not the default triggers'
            cand --dry-run 'Print the link, directory and settings it would record with, and exit without opening the link'
            cand --status 'Is a recorder running in DIR: since when, frames recorded and lost, the ring, the last incidents'
            cand --list 'The incidents in DIR, oldest first'
            cand --mark 'Leave a mark (with NOTE): the running recorder keeps an incident around now'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;report'= {
            cand -o 'The bundle''s file, or a directory to write the default name in [default: tracerctl-report-HOST-TIME.tar.gz here]'
            cand --output 'The bundle''s file, or a directory to write the default name in [default: tracerctl-report-HOST-TIME.tar.gz here]'
            cand --dir 'The recorder''s directory [default: /var/lib/tracerctl/record, if there is one]'
            cand --listen 'How long to listen to the robot (100ms to 10m); its frames are kept when no recorder runs'
            cand --max-size 'The cap on the bundle''s size: 50MB, 500kB, 1GiB (kB, MB, GB are powers of 1000; KiB, MiB, GiB of 1024)'
            cand --incidents 'How many incidents to take, newest first'
            cand --ring-minutes 'How many minutes of the recorder''s ring to take (its last ones)'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --force 'Replace an existing file of that name'
            cand --probe 'Also run the doctor''s probe: it sends a mode command and zero-velocity motion, never moving the robot'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;completions'= {
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;config'= {
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand show 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default'
            cand path 'The configuration files looked for, in order, and which exist (reads none of them)'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'tracerctl;config;show'= {
            cand -f 'Text, or JSON (docs/json.md)'
            cand --format 'Text, or JSON (docs/json.md)'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;config;path'= {
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (an explicit always or never overrides NO_COLOR)'
            cand --profile 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)'
            cand --iface 'CAN interface [default: $TRACERCTL_IFACE or can0]'
            cand --serial 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)'
            cand --baud 'Serial baud rate (with --serial) [default: 115200]'
            cand --fault 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)'
            cand --replay 'Play back a candump log as a read-only source (for monitor, dashboard)'
            cand --speed 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]'
            cand --sim 'Drive an in-process virtual TRACER, not a robot'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;config;help'= {
            cand show 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default'
            cand path 'The configuration files looked for, in order, and which exist (reads none of them)'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'tracerctl;config;help;show'= {
        }
        &'tracerctl;config;help;path'= {
        }
        &'tracerctl;config;help;help'= {
        }
        &'tracerctl;help'= {
            cand decode 'Decode candump logs, single frames or RS232 captures'
            cand monitor 'Watch the live bus, decoded, with warnings when periodic frames go stale'
            cand drive 'Drive at a fixed speed: 50 Hz commands, ramped and capped; Ctrl-C stops it'
            cand doctor 'Why isn''t it moving? Check the link, bus, protocol, mode, E-stop, faults and battery (PASS/WARN/FAIL)'
            cand mode 'Switch the control mode (0x421) and report it before and after'
            cand clear-errors 'Clear latched faults (0x441) and report which bits cleared and which remain'
            cand lights 'Set the lights (0x121), confirmed from the light state (0x231)'
            cand send-raw 'Show what raw frames mean, then send them (cansend syntax, or hex RS232 frames)'
            cand sim 'Run a virtual TRACER on a CAN interface (e.g. --iface vcan0) or a new pseudo-terminal (--pty)'
            cand dashboard 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive'
            cand record 'Black box: record the bus unattended, keep the minutes around each fault as an incident; never sends'
            cand report 'Make the support bundle for the vendor: doctor, firmware version, rates, incidents, host facts'
            cand completions 'Print a shell completion script to standard output'
            cand config 'The configuration files: every effective setting with its source (show), the files read (path)'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'tracerctl;help;decode'= {
        }
        &'tracerctl;help;monitor'= {
        }
        &'tracerctl;help;drive'= {
        }
        &'tracerctl;help;doctor'= {
        }
        &'tracerctl;help;mode'= {
        }
        &'tracerctl;help;clear-errors'= {
        }
        &'tracerctl;help;lights'= {
        }
        &'tracerctl;help;send-raw'= {
        }
        &'tracerctl;help;sim'= {
        }
        &'tracerctl;help;dashboard'= {
        }
        &'tracerctl;help;record'= {
        }
        &'tracerctl;help;report'= {
        }
        &'tracerctl;help;completions'= {
        }
        &'tracerctl;help;config'= {
            cand show 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default'
            cand path 'The configuration files looked for, in order, and which exist (reads none of them)'
        }
        &'tracerctl;help;config;show'= {
        }
        &'tracerctl;help;config;path'= {
        }
        &'tracerctl;help;help'= {
        }
    ]
    $completions[$command]
}
