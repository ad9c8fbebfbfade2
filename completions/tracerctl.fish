# Print an optspec for argparse to handle cmd's options that are independent of any subcommand.
function __fish_tracerctl_global_optspecs
    string join \n protocol= color= h/help V/version
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
complete -c tracerctl -n "__fish_tracerctl_needs_command" -l color -d 'When to colour output (colour is never used with NO_COLOR set)' -r -f -a "auto\t''
always\t''
never\t''"
complete -c tracerctl -n "__fish_tracerctl_needs_command" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "decode" -d 'Decode candump logs, single frames or RS232 captures'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "completions" -d 'Print a shell completion script to standard output'
complete -c tracerctl -n "__fish_tracerctl_needs_command" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l serial -d 'RS232 capture to decode: raw bytes, or hex text such as "5A A5 0A 55 ..."' -r -F
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s f -l format -d 'Output format' -r -f -a "text\t'One readable line per frame'
json\t'One JSON object per line (schema in docs/json.md)'
csv\t'Comma-separated values with a fixed header (for spreadsheets)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l id -d 'Only frames with these identifiers (hex, comma-separated: 0x211,221, or AA01 for serial)' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l msg -d 'Only these messages (comma-separated), e.g. system_state,odometry; also raw, invalid, error_frame' -r
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l color -d 'When to colour output (colour is never used with NO_COLOR set)' -r -f -a "auto\t''
always\t''
never\t''"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s s -l summary -d 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l strict -d 'Stop at the first bad line, bad frame or corrupted serial frame (exit status 3)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l delta-stamps -d 'Console timestamps are deltas between frames (candump -t d): add them up. Such stamps look exactly like -t z ones, so this cannot be detected'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -l no-progress -d 'Never show a progress bar (it is shown only on a terminal, for large files)'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand decode" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l protocol -d 'Protocol version: auto detects from the identifiers on the bus' -r -f -a "auto\t'Decide from the traffic'
v1\t'CAN protocol V1 (older firmware, checksummed frames)'
v2\t'CAN protocol V2 (current firmware)'"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -l color -d 'When to colour output (colour is never used with NO_COLOR set)' -r -f -a "auto\t''
always\t''
never\t''"
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand completions" -s V -l version -d 'Print version'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode completions help" -f -a "decode" -d 'Decode candump logs, single frames or RS232 captures'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode completions help" -f -a "completions" -d 'Print a shell completion script to standard output'
complete -c tracerctl -n "__fish_tracerctl_using_subcommand help; and not __fish_seen_subcommand_from decode completions help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
