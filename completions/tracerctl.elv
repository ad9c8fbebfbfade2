
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
            cand --color 'When to colour output (colour is never used with NO_COLOR set)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand decode 'Decode candump logs, single frames or RS232 captures'
            cand completions 'Print a shell completion script to standard output'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'tracerctl;decode'= {
            cand --serial 'RS232 capture to decode: raw bytes, or hex text such as "5A A5 0A 55 ..."'
            cand -f 'Output format'
            cand --format 'Output format'
            cand --id 'Only frames with these identifiers (hex, comma-separated: 0x211,221, or AA01 for serial)'
            cand --msg 'Only these messages (comma-separated), e.g. system_state,odometry; also raw, invalid, error_frame'
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (colour is never used with NO_COLOR set)'
            cand -s 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance'
            cand --summary 'Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance'
            cand --strict 'Stop at the first bad line, bad frame or corrupted serial frame (exit status 3)'
            cand --delta-stamps 'Console timestamps are deltas between frames (candump -t d): add them up. Such stamps look exactly like -t z ones, so this cannot be detected'
            cand --no-progress 'Never show a progress bar (it is shown only on a terminal, for large files)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;completions'= {
            cand --protocol 'Protocol version: auto detects from the identifiers on the bus'
            cand --color 'When to colour output (colour is never used with NO_COLOR set)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'tracerctl;help'= {
            cand decode 'Decode candump logs, single frames or RS232 captures'
            cand completions 'Print a shell completion script to standard output'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'tracerctl;help;decode'= {
        }
        &'tracerctl;help;completions'= {
        }
        &'tracerctl;help;help'= {
        }
    ]
    $completions[$command]
}
