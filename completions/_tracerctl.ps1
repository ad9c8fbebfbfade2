
using namespace System.Management.Automation
using namespace System.Management.Automation.Language

Register-ArgumentCompleter -Native -CommandName 'tracerctl' -ScriptBlock {
    param($wordToComplete, $commandAst, $cursorPosition)

    $commandElements = $commandAst.CommandElements
    $command = @(
        'tracerctl'
        for ($i = 1; $i -lt $commandElements.Count; $i++) {
            $element = $commandElements[$i]
            if ($element -isnot [StringConstantExpressionAst] -or
                $element.StringConstantType -ne [StringConstantType]::BareWord -or
                $element.Value.StartsWith('-') -or
                $element.Value -eq $wordToComplete) {
                break
        }
        $element.Value
    }) -join ';'

    $completions = @(switch ($command) {
        'tracerctl' {
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('decode', 'decode', [CompletionResultType]::ParameterValue, 'Decode candump logs, single frames or RS232 captures')
            [CompletionResult]::new('monitor', 'monitor', [CompletionResultType]::ParameterValue, 'Watch the live bus, decoded, with warnings when periodic frames go stale')
            [CompletionResult]::new('drive', 'drive', [CompletionResultType]::ParameterValue, 'Drive at a fixed speed: 50 Hz commands, ramped and capped; Ctrl-C stops it')
            [CompletionResult]::new('commission', 'commission', [CompletionResultType]::ParameterValue, 'Acceptance test drive: measure how the robot answers, PASS/WARN/FAIL per figure')
            [CompletionResult]::new('doctor', 'doctor', [CompletionResultType]::ParameterValue, 'Why isn''t it moving? Check the link, bus, protocol, mode, E-stop, faults and battery (PASS/WARN/FAIL)')
            [CompletionResult]::new('mode', 'mode', [CompletionResultType]::ParameterValue, 'Switch the control mode (0x421) and report it before and after')
            [CompletionResult]::new('clear-errors', 'clear-errors', [CompletionResultType]::ParameterValue, 'Clear latched faults (0x441) and report which bits cleared and which remain')
            [CompletionResult]::new('lights', 'lights', [CompletionResultType]::ParameterValue, 'Set the lights (0x121), confirmed from the light state (0x231)')
            [CompletionResult]::new('send-raw', 'send-raw', [CompletionResultType]::ParameterValue, 'Show what raw frames mean, then send them (cansend syntax, or hex RS232 frames)')
            [CompletionResult]::new('sim', 'sim', [CompletionResultType]::ParameterValue, 'Run a virtual TRACER on a CAN interface (e.g. --iface vcan0) or a new pseudo-terminal (--pty)')
            [CompletionResult]::new('dashboard', 'dashboard', [CompletionResultType]::ParameterValue, 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive')
            [CompletionResult]::new('dash', 'dash', [CompletionResultType]::ParameterValue, 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive')
            [CompletionResult]::new('record', 'record', [CompletionResultType]::ParameterValue, 'Black box: record the bus unattended, keep the minutes around each fault as an incident; never sends')
            [CompletionResult]::new('report', 'report', [CompletionResultType]::ParameterValue, 'Make the support bundle for the vendor: doctor, firmware version, rates, incidents, host facts')
            [CompletionResult]::new('completions', 'completions', [CompletionResultType]::ParameterValue, 'Print a shell completion script to standard output')
            [CompletionResult]::new('config', 'config', [CompletionResultType]::ParameterValue, 'The configuration files: every effective setting with its source (show), the files read (path)')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'tracerctl;decode' {
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'Output format [default: text, or mcap for -o FILE.mcap]. MCAP (Foxglove, PlotJuggler) needs -o FILE and is written by one thread')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format [default: text, or mcap for -o FILE.mcap]. MCAP (Foxglove, PlotJuggler) needs -o FILE and is written by one thread')
            [CompletionResult]::new('-o', '-o', [CompletionResultType]::ParameterName, 'Write the output to FILE instead of standard output (a .mcap name means --format mcap)')
            [CompletionResult]::new('--output', '--output', [CompletionResultType]::ParameterName, 'Write the output to FILE instead of standard output (a .mcap name means --format mcap)')
            [CompletionResult]::new('--mcap-compression', '--mcap-compression', [CompletionResultType]::ParameterName, 'Chunk compression of MCAP output')
            [CompletionResult]::new('--id', '--id', [CompletionResultType]::ParameterName, 'Only frames with these identifiers (hex, comma-separated: 0x211,221, or AA01 for serial)')
            [CompletionResult]::new('--msg', '--msg', [CompletionResultType]::ParameterName, 'Only these messages (comma-separated), e.g. system_state,odometry; also raw, invalid, error_frame')
            [CompletionResult]::new('--plot', '--plot', [CompletionResultType]::ParameterName, 'Draw battery voltage, commanded vs measured speeds, motor RPM and current, with fault and E-stop events marked, as an SVG file')
            [CompletionResult]::new('-j', '-j', [CompletionResultType]::ParameterName, 'Threads for text logs (candump, Vector ASC, PEAK trc): files and standard input, plain or compressed, in every mode (--summary, --plot, --delta-stamps too; default: all cores; 1: one)')
            [CompletionResult]::new('--threads', '--threads', [CompletionResultType]::ParameterName, 'Threads for text logs (candump, Vector ASC, PEAK trc): files and standard input, plain or compressed, in every mode (--summary, --plot, --delta-stamps too; default: all cores; 1: one)')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('-s', '-s', [CompletionResultType]::ParameterName, 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance')
            [CompletionResult]::new('--summary', '--summary', [CompletionResultType]::ParameterName, 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance')
            [CompletionResult]::new('--strict', '--strict', [CompletionResultType]::ParameterName, 'Stop at the first bad line, bad frame or corrupted serial frame (exit status 3)')
            [CompletionResult]::new('--delta-stamps', '--delta-stamps', [CompletionResultType]::ParameterName, 'Console timestamps are deltas between frames (candump -t d): add them up. Such stamps look exactly like those of candump -t z, so tracerctl cannot tell them apart')
            [CompletionResult]::new('--no-progress', '--no-progress', [CompletionResultType]::ParameterName, 'Never show a progress bar (shown only for large files, on a terminal)')
            [CompletionResult]::new('--no-mmap', '--no-mmap', [CompletionResultType]::ParameterName, 'Read files with positioned reads only, never mapped into memory (also TRACERCTL_NO_MMAP=1); the output is the same')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;monitor' {
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--id', '--id', [CompletionResultType]::ParameterName, 'Only frames with these identifiers (comma-separated hex numbers)')
            [CompletionResult]::new('--msg', '--msg', [CompletionResultType]::ParameterName, 'Only these messages, e.g. system_state,odometry (see --help for all)')
            [CompletionResult]::new('--log', '--log', [CompletionResultType]::ParameterName, 'Also write every frame to FILE in candump -L format (replayable with canplayer), flushed per line; a .mcap name writes MCAP instead (docs/foxglove.md), flushed every second')
            [CompletionResult]::new('--duration', '--duration', [CompletionResultType]::ParameterName, 'Stop after this long (e.g. 10s; up to 30 days); default: until Ctrl-C')
            [CompletionResult]::new('--silence', '--silence', [CompletionResultType]::ParameterName, 'Warn when the bus is silent this long (0 to 1h; 0: never)')
            [CompletionResult]::new('-t', '-t', [CompletionResultType]::ParameterName, 'Time column of text lines, as candump -t: a, d, z or A (default: absolute)')
            [CompletionResult]::new('--timestamp', '--timestamp', [CompletionResultType]::ParameterName, 'Time column of text lines, as candump -t: a, d, z or A (default: absolute)')
            [CompletionResult]::new('-n', '-n', [CompletionResultType]::ParameterName, 'Exit after COUNT frames shown (as candump -n), with the summary; exit status 0')
            [CompletionResult]::new('--count', '--count', [CompletionResultType]::ParameterName, 'Exit after COUNT frames shown (as candump -n), with the summary; exit status 0')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--raw', '--raw', [CompletionResultType]::ParameterName, 'Print frames as candump -L lines, undecoded (so not with --format)')
            [CompletionResult]::new('--no-data', '--no-data', [CompletionResultType]::ParameterName, 'Leave the raw bytes out of text lines (the line decode prints, for scripts that parse it)')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;drive' {
            [CompletionResult]::new('--linear', '--linear', [CompletionResultType]::ParameterName, 'Linear speed in m/s (+ forward; -100 to 100, capped at --max-linear); 0 when only --angular is given')
            [CompletionResult]::new('--angular', '--angular', [CompletionResultType]::ParameterName, 'Angular speed in rad/s (+ turns counter-clockwise; -100 to 100, capped at --max-angular); 0 when only --linear is given')
            [CompletionResult]::new('--for', '--for', [CompletionResultType]::ParameterName, 'How long to drive (e.g. 2s, 1500ms; up to 24h); default: until Ctrl-C')
            [CompletionResult]::new('--duration', '--duration', [CompletionResultType]::ParameterName, 'How long to drive (e.g. 2s, 1500ms; up to 24h); default: until Ctrl-C')
            [CompletionResult]::new('--max-linear', '--max-linear', [CompletionResultType]::ParameterName, 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)')
            [CompletionResult]::new('--max-angular', '--max-angular', [CompletionResultType]::ParameterName, 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)')
            [CompletionResult]::new('--accel', '--accel', [CompletionResultType]::ParameterName, 'Linear acceleration of the ramp, m/s²')
            [CompletionResult]::new('--angular-accel', '--angular-accel', [CompletionResultType]::ParameterName, 'Angular acceleration of the ramp, rad/s²')
            [CompletionResult]::new('--decel', '--decel', [CompletionResultType]::ParameterName, 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s')
            [CompletionResult]::new('--angular-decel', '--angular-decel', [CompletionResultType]::ParameterName, 'Angular braking, rad/s²; at least --angular-accel')
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'Status lines and final report on stdout: text, or JSON (docs/json.md)')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Status lines and final report on stdout: text, or JSON (docs/json.md)')
            [CompletionResult]::new('--record', '--record', [CompletionResultType]::ParameterName, 'Record the frames received and sent to FILE (candump log; MCAP for a .mcap name)')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--ignore-faults', '--ignore-faults', [CompletionResultType]::ParameterName, 'Start even with the E-stop pressed or a latched fault (the robot may still refuse)')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;commission' {
            [CompletionResult]::new('--max-linear', '--max-linear', [CompletionResultType]::ParameterName, 'Cap on the linear speed of the steps, m/s (at most 0.6 is used: the 1 m straight must hold a step)')
            [CompletionResult]::new('--max-angular', '--max-angular', [CompletionResultType]::ParameterName, 'Cap on the angular speed of the spins, rad/s (at most 0.7853 is used)')
            [CompletionResult]::new('--include', '--include', [CompletionResultType]::ParameterName, 'Add an opt-in step (repeatable)')
            [CompletionResult]::new('--record', '--record', [CompletionResultType]::ParameterName, 'Write a candump log of the run (frames received and sent) to FILE; a .mcap name writes MCAP')
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'The report on stdout: text, or one JSON object (docs/commission.md)')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'The report on stdout: text, or one JSON object (docs/commission.md)')
            [CompletionResult]::new('--plot', '--plot', [CompletionResultType]::ParameterName, 'Draw each step (commanded, measured and wheel speeds) into FILE.svg')
            [CompletionResult]::new('--save', '--save', [CompletionResultType]::ParameterName, 'Keep the JSON record as DIR/<link>-<UTC time>.json (never overwriting)')
            [CompletionResult]::new('--compare', '--compare', [CompletionResultType]::ParameterName, 'After the run, show each figure''s old and new value and flag what drifted since OLD.json')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--yes', '--yes', [CompletionResultType]::ParameterName, 'Drive without asking on the terminal (the operator has checked the free space)')
            [CompletionResult]::new('--dry-run', '--dry-run', [CompletionResultType]::ParameterName, 'Print the steps, the bounds and the duration, and exit: no link opened, nothing sent')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;doctor' {
            [CompletionResult]::new('--listen', '--listen', [CompletionResultType]::ParameterName, 'How long to listen to the robot (100ms to 10m)')
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'Format of the report')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Format of the report')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--probe', '--probe', [CompletionResultType]::ParameterName, 'Also check that the robot accepts commands: control mode and zero-velocity motion (it does not move)')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;mode' {
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for the robot to confirm (0 to 10m)')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;clear-errors' {
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to watch the status afterwards (0 to 10m)')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;lights' {
            [CompletionResult]::new('--front', '--front', [CompletionResultType]::ParameterName, 'Front light mode')
            [CompletionResult]::new('--brightness', '--brightness', [CompletionResultType]::ParameterName, 'Front brightness for --front custom, percent (0-100)')
            [CompletionResult]::new('--rear', '--rear', [CompletionResultType]::ParameterName, 'Rear light mode (reserved on TRACER: the firmware ignores it)')
            [CompletionResult]::new('--rear-brightness', '--rear-brightness', [CompletionResultType]::ParameterName, 'Rear brightness for --rear custom, percent (0-100)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for the light state to confirm (0 to 10m)')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--release', '--release', [CompletionResultType]::ParameterName, 'Hand the lights back to the firmware')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;send-raw' {
            [CompletionResult]::new('--repeat', '--repeat', [CompletionResultType]::ParameterName, 'Send the frames this many times')
            [CompletionResult]::new('--period', '--period', [CompletionResultType]::ParameterName, 'Time between repeats, milliseconds')
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'What was sent, on stdout, as text or JSON (docs/json.md); diagnostics go to stderr')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'What was sent, on stdout, as text or JSON (docs/json.md); diagnostics go to stderr')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--force', '--force', [CompletionResultType]::ParameterName, 'Allow frames that can move the robot (0x111, 0x130, 0x421, RS232 motion control), and frames the robot would reject (a TRACER identifier with the wrong length or checksum)')
            [CompletionResult]::new('--fix-checksum', '--fix-checksum', [CompletionResultType]::ParameterName, 'Compute RS232 checksums instead of requiring them')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;sim' {
            [CompletionResult]::new('--rc', '--rc', [CompletionResultType]::ParameterName, 'An RC transmitter is on, with SWB in this position (middle = RC mode overrides commands)')
            [CompletionResult]::new('--battery', '--battery', [CompletionResultType]::ParameterName, 'Starting battery voltage (18 to 30)')
            [CompletionResult]::new('--drain', '--drain', [CompletionResultType]::ParameterName, 'Speed up battery drain by this factor (to see the low-battery warnings quickly; 0 to 1000000)')
            [CompletionResult]::new('--duration', '--duration', [CompletionResultType]::ParameterName, 'Stop after this long (at most 30 days); default: until Ctrl-C')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--pty', '--pty', [CompletionResultType]::ParameterName, 'Serve on a new pseudo-terminal (prints its path) instead of a CAN interface or --serial port')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;dashboard' {
            [CompletionResult]::new('--max-linear', '--max-linear', [CompletionResultType]::ParameterName, 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)')
            [CompletionResult]::new('--max-angular', '--max-angular', [CompletionResultType]::ParameterName, 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)')
            [CompletionResult]::new('--accel', '--accel', [CompletionResultType]::ParameterName, 'Linear acceleration of the ramp, m/s²')
            [CompletionResult]::new('--angular-accel', '--angular-accel', [CompletionResultType]::ParameterName, 'Angular acceleration of the ramp, rad/s²')
            [CompletionResult]::new('--decel', '--decel', [CompletionResultType]::ParameterName, 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s')
            [CompletionResult]::new('--angular-decel', '--angular-decel', [CompletionResultType]::ParameterName, 'Angular braking, rad/s²; at least --angular-accel')
            [CompletionResult]::new('--record', '--record', [CompletionResultType]::ParameterName, 'Write a candump log of the session (frames received and sent) to FILE; a .mcap name writes MCAP (Foxglove, PlotJuggler: docs/foxglove.md)')
            [CompletionResult]::new('--key-timeout', '--key-timeout', [CompletionResultType]::ParameterName, 'Without key-release events (tmux, most terminals over SSH): a held key counts as released when no auto-repeat came for DURATION (20ms to 1.25s), instead of the deadline learned from the key stream. Longer rides out a jittery link, shorter stops sooner')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--watch', '--watch', [CompletionResultType]::ParameterName, 'Watch only: never arm driving, never send anything (for a robot that ROS or an RC transmitter drives)')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;dash' {
            [CompletionResult]::new('--max-linear', '--max-linear', [CompletionResultType]::ParameterName, 'Cap on the linear speed, m/s (above 0; at most 1.5 is used)')
            [CompletionResult]::new('--max-angular', '--max-angular', [CompletionResultType]::ParameterName, 'Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)')
            [CompletionResult]::new('--accel', '--accel', [CompletionResultType]::ParameterName, 'Linear acceleration of the ramp, m/s²')
            [CompletionResult]::new('--angular-accel', '--angular-accel', [CompletionResultType]::ParameterName, 'Angular acceleration of the ramp, rad/s²')
            [CompletionResult]::new('--decel', '--decel', [CompletionResultType]::ParameterName, 'Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s')
            [CompletionResult]::new('--angular-decel', '--angular-decel', [CompletionResultType]::ParameterName, 'Angular braking, rad/s²; at least --angular-accel')
            [CompletionResult]::new('--record', '--record', [CompletionResultType]::ParameterName, 'Write a candump log of the session (frames received and sent) to FILE; a .mcap name writes MCAP (Foxglove, PlotJuggler: docs/foxglove.md)')
            [CompletionResult]::new('--key-timeout', '--key-timeout', [CompletionResultType]::ParameterName, 'Without key-release events (tmux, most terminals over SSH): a held key counts as released when no auto-repeat came for DURATION (20ms to 1.25s), instead of the deadline learned from the key stream. Longer rides out a jittery link, shorter stops sooner')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--watch', '--watch', [CompletionResultType]::ParameterName, 'Watch only: never arm driving, never send anything (for a robot that ROS or an RC transmitter drives)')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;record' {
            [CompletionResult]::new('--dir', '--dir', [CompletionResultType]::ParameterName, 'The recorder directory [default: $XDG_STATE_HOME/tracerctl/record, or for --status, --list and --mark the one recorder directory under /var/lib/tracerctl when there is only one]')
            [CompletionResult]::new('--segment', '--segment', [CompletionResultType]::ParameterName, 'A new segment this often (1s to 1d)')
            [CompletionResult]::new('--max-total', '--max-total', [CompletionResultType]::ParameterName, 'The ring''s size, e.g. 1GiB, 500MB (at least 1 MiB)')
            [CompletionResult]::new('--max-age', '--max-age', [CompletionResultType]::ParameterName, 'Segments older than this are removed (1m to 366d)')
            [CompletionResult]::new('--before', '--before', [CompletionResultType]::ParameterName, 'An incident keeps the frames from this long before its trigger, from 0 to 1h')
            [CompletionResult]::new('--after', '--after', [CompletionResultType]::ParameterName, '... to this long after it (0 to 1h); a trigger inside the window extends it')
            [CompletionResult]::new('--max-incidents', '--max-incidents', [CompletionResultType]::ParameterName, 'Incidents kept, the oldest removed first')
            [CompletionResult]::new('--trigger', '--trigger', [CompletionResultType]::ParameterName, 'Also a trigger (repeatable): a decoded field and a value, e.g. ''battery_voltage<23.0'' or ''id=0x441''')
            [CompletionResult]::new('--instance', '--instance', [CompletionResultType]::ParameterName, 'The link from a systemd instance name: a profile, can0 (SocketCAN), or ttyUSB0, dev/ttyUSB0 (serial)')
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'Output format of --status and --list')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format of --status and --list')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--no-default-triggers', '--no-default-triggers', [CompletionResultType]::ParameterName, 'Only the --trigger expressions and marks, not the default triggers')
            [CompletionResult]::new('--dry-run', '--dry-run', [CompletionResultType]::ParameterName, 'Print the link, directory and settings it would record with, and exit without opening the link')
            [CompletionResult]::new('--status', '--status', [CompletionResultType]::ParameterName, 'Is a recorder running in DIR: since when, frames recorded and lost, the ring, the last incidents')
            [CompletionResult]::new('--list', '--list', [CompletionResultType]::ParameterName, 'The incidents in DIR, oldest first')
            [CompletionResult]::new('--mark', '--mark', [CompletionResultType]::ParameterName, 'Leave a mark (with NOTE): the running recorder keeps an incident around now')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;report' {
            [CompletionResult]::new('-o', '-o', [CompletionResultType]::ParameterName, 'The bundle''s file, or a directory to write the default name in [default: tracerctl-report-HOST-TIME.tar.gz here]')
            [CompletionResult]::new('--output', '--output', [CompletionResultType]::ParameterName, 'The bundle''s file, or a directory to write the default name in [default: tracerctl-report-HOST-TIME.tar.gz here]')
            [CompletionResult]::new('--dir', '--dir', [CompletionResultType]::ParameterName, 'The recorder''s directory [default: /var/lib/tracerctl/record, if there is one]')
            [CompletionResult]::new('--listen', '--listen', [CompletionResultType]::ParameterName, 'How long to listen to the robot (100ms to 10m); its frames are kept when no recorder runs')
            [CompletionResult]::new('--max-size', '--max-size', [CompletionResultType]::ParameterName, 'The cap on the bundle''s size: 50MB, 500kB, 1GiB (kB, MB, GB are powers of 1000; KiB, MiB, GiB of 1024)')
            [CompletionResult]::new('--incidents', '--incidents', [CompletionResultType]::ParameterName, 'How many incidents to take, newest first')
            [CompletionResult]::new('--ring-minutes', '--ring-minutes', [CompletionResultType]::ParameterName, 'How many minutes of the recorder''s ring to take (its last ones)')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--force', '--force', [CompletionResultType]::ParameterName, 'Replace an existing file of that name')
            [CompletionResult]::new('--probe', '--probe', [CompletionResultType]::ParameterName, 'Also run the doctor''s probe: it sends a mode command and zero-velocity motion, never moving the robot')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;completions' {
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;config' {
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('show', 'show', [CompletionResultType]::ParameterValue, 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default')
            [CompletionResult]::new('path', 'path', [CompletionResultType]::ParameterValue, 'The configuration files looked for, in order, and which exist (reads none of them)')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'tracerctl;config;show' {
            [CompletionResult]::new('-f', '-f', [CompletionResultType]::ParameterName, 'Text, or JSON (docs/json.md)')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Text, or JSON (docs/json.md)')
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;config;path' {
            [CompletionResult]::new('--protocol', '--protocol', [CompletionResultType]::ParameterName, 'Protocol version: auto detects from the identifiers on the bus')
            [CompletionResult]::new('--color', '--color', [CompletionResultType]::ParameterName, 'When to colour output (an explicit always or never overrides NO_COLOR)')
            [CompletionResult]::new('--profile', '--profile', [CompletionResultType]::ParameterName, 'Settings of this robot''s profile in the configuration files ([profiles.NAME]; tracerctl config show)')
            [CompletionResult]::new('--iface', '--iface', [CompletionResultType]::ParameterName, 'CAN interface [default: $TRACERCTL_IFACE or can0]')
            [CompletionResult]::new('--serial', '--serial', [CompletionResultType]::ParameterName, 'RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Serial baud rate (with --serial) [default: 115200]')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--sim-param', '--sim-param', [CompletionResultType]::ParameterName, 'Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)')
            [CompletionResult]::new('--replay', '--replay', [CompletionResultType]::ParameterName, 'Play back a candump log as a read-only source (for monitor, dashboard)')
            [CompletionResult]::new('--speed', '--speed', [CompletionResultType]::ParameterName, 'Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]')
            [CompletionResult]::new('--sim', '--sim', [CompletionResultType]::ParameterName, 'Drive an in-process virtual TRACER, not a robot')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'tracerctl;config;help' {
            [CompletionResult]::new('show', 'show', [CompletionResultType]::ParameterValue, 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default')
            [CompletionResult]::new('path', 'path', [CompletionResultType]::ParameterValue, 'The configuration files looked for, in order, and which exist (reads none of them)')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'tracerctl;config;help;show' {
            break
        }
        'tracerctl;config;help;path' {
            break
        }
        'tracerctl;config;help;help' {
            break
        }
        'tracerctl;help' {
            [CompletionResult]::new('decode', 'decode', [CompletionResultType]::ParameterValue, 'Decode candump logs, single frames or RS232 captures')
            [CompletionResult]::new('monitor', 'monitor', [CompletionResultType]::ParameterValue, 'Watch the live bus, decoded, with warnings when periodic frames go stale')
            [CompletionResult]::new('drive', 'drive', [CompletionResultType]::ParameterValue, 'Drive at a fixed speed: 50 Hz commands, ramped and capped; Ctrl-C stops it')
            [CompletionResult]::new('commission', 'commission', [CompletionResultType]::ParameterValue, 'Acceptance test drive: measure how the robot answers, PASS/WARN/FAIL per figure')
            [CompletionResult]::new('doctor', 'doctor', [CompletionResultType]::ParameterValue, 'Why isn''t it moving? Check the link, bus, protocol, mode, E-stop, faults and battery (PASS/WARN/FAIL)')
            [CompletionResult]::new('mode', 'mode', [CompletionResultType]::ParameterValue, 'Switch the control mode (0x421) and report it before and after')
            [CompletionResult]::new('clear-errors', 'clear-errors', [CompletionResultType]::ParameterValue, 'Clear latched faults (0x441) and report which bits cleared and which remain')
            [CompletionResult]::new('lights', 'lights', [CompletionResultType]::ParameterValue, 'Set the lights (0x121), confirmed from the light state (0x231)')
            [CompletionResult]::new('send-raw', 'send-raw', [CompletionResultType]::ParameterValue, 'Show what raw frames mean, then send them (cansend syntax, or hex RS232 frames)')
            [CompletionResult]::new('sim', 'sim', [CompletionResultType]::ParameterValue, 'Run a virtual TRACER on a CAN interface (e.g. --iface vcan0) or a new pseudo-terminal (--pty)')
            [CompletionResult]::new('dashboard', 'dashboard', [CompletionResultType]::ParameterValue, 'Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive')
            [CompletionResult]::new('record', 'record', [CompletionResultType]::ParameterValue, 'Black box: record the bus unattended, keep the minutes around each fault as an incident; never sends')
            [CompletionResult]::new('report', 'report', [CompletionResultType]::ParameterValue, 'Make the support bundle for the vendor: doctor, firmware version, rates, incidents, host facts')
            [CompletionResult]::new('completions', 'completions', [CompletionResultType]::ParameterValue, 'Print a shell completion script to standard output')
            [CompletionResult]::new('config', 'config', [CompletionResultType]::ParameterValue, 'The configuration files: every effective setting with its source (show), the files read (path)')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'tracerctl;help;decode' {
            break
        }
        'tracerctl;help;monitor' {
            break
        }
        'tracerctl;help;drive' {
            break
        }
        'tracerctl;help;commission' {
            break
        }
        'tracerctl;help;doctor' {
            break
        }
        'tracerctl;help;mode' {
            break
        }
        'tracerctl;help;clear-errors' {
            break
        }
        'tracerctl;help;lights' {
            break
        }
        'tracerctl;help;send-raw' {
            break
        }
        'tracerctl;help;sim' {
            break
        }
        'tracerctl;help;dashboard' {
            break
        }
        'tracerctl;help;record' {
            break
        }
        'tracerctl;help;report' {
            break
        }
        'tracerctl;help;completions' {
            break
        }
        'tracerctl;help;config' {
            [CompletionResult]::new('show', 'show', [CompletionResultType]::ParameterValue, 'Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default')
            [CompletionResult]::new('path', 'path', [CompletionResultType]::ParameterValue, 'The configuration files looked for, in order, and which exist (reads none of them)')
            break
        }
        'tracerctl;help;config;show' {
            break
        }
        'tracerctl;help;config;path' {
            break
        }
        'tracerctl;help;help' {
            break
        }
    })

    $completions.Where{ $_.CompletionText -like "$wordToComplete*" } |
        Sort-Object -Property ListItemText
}
