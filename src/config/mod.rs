//! The configuration file and its per-robot profiles: `/etc/tracerctl/config.toml`, then
//! `$XDG_CONFIG_HOME/tracerctl/config.toml`; a value's precedence is flag > environment > profile > file >
//! built-in default.
