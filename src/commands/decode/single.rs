//! One thread's decoding of a text log (`-j1`): the splitter's runs of whole lines through the line loop
//! into the [`Decoder`], which writes at once and stops at the first error (`--strict`, a failed write).

use std::io::Read;
use std::ops::ControlFlow;

use anyhow::Result;

use super::damaged::Reached;
use super::lines::{decode_lines, FrameLine, LineSink};
use super::splitter::{Cut, Splitter, Text};
use super::written::in_line;
use super::{parallel, Decoder, CAN_XL_NOT_SUPPORTED};
use crate::candump::{self, Line, LineParser, LogFormat, Reason};
use crate::exit::Failure;

impl Decoder {
    /// Decodes a text log on this thread; a `stream` (standard input, a pipe, a device) is decoded as each
    /// read returns, so a live stream's lines are written as they arrive.
    pub(super) fn candump(
        &mut self,
        name: &str,
        input: impl Read,
        (size, stream): (Option<u64>, bool),
        format: LogFormat,
    ) -> Result<()> {
        let parser = LineParser::for_format(format);
        let mut parser = if self.delta_stamps { parser.with_delta_timestamps() } else { parser };
        let bar = self.progress_bar(size);
        let before = self.input_start();
        let cut = Cut { chunk_bytes: parallel::CHUNK_BYTES, stream };
        let mut splitter = Splitter::new(self.live(input), cut);
        let (mut text, mut consumed) = (Text::default(), 0);
        while splitter.next_text(&mut text).is_some() {
            let first = self.stats.lines - before.lines + 1;
            let mut sink = DecoderLines { decoder: self, name, error: None };
            let scanned = decode_lines(&mut sink, &mut parser, (&text.input[..], &text.long_lines), first);
            let error = sink.error;
            self.stats.lines += scanned.lines;
            if let Some(error) = error {
                return Err(error);
            }
            consumed += text.bytes;
            if let Some(bar) = &bar {
                bar.set_position(consumed);
            }
            if let Some(error) = text.read_error.take() {
                let reached = Reached { lines: self.stats.lines - before.lines, unfinished: text.unfinished };
                self.read_failed(name, error, reached)?;
                break;
            }
        }
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        self.note_no_frames(name, before);
        Ok(())
    }

    /// A line that is not a frame: counted by kind (a CAN XL frame is an error with --strict).
    #[inline(never)]
    fn skipped_line(&mut self, name: &str, number: u64, line: Line<'_>) -> Result<()> {
        let dropped = self.stats.skipped.count(&line);
        self.stats.candump_dropped = self.stats.candump_dropped.saturating_add(dropped);
        if matches!(line, Line::CanXl) && self.strict {
            return Err(Failure::data(format!("{name}:{number}: {CAN_XL_NOT_SUPPORTED}")).into());
        }
        Ok(())
    }

    /// A line the log format does not read: a bare cansend frame (a file of "211#00000103000000B1" lines is
    /// read too), or a rejected line with the reason.
    #[inline(never)]
    fn unparsed_line(
        &mut self,
        name: &str,
        number: u64,
        text: &[u8],
        error: candump::LineError,
    ) -> Result<()> {
        let bare = text.trim_ascii();
        let looks_bare = bare.contains(&b'#') && !bare.iter().any(u8::is_ascii_whitespace);
        match candump::parse_cansend(bare) {
            Ok(frame) => {
                self.stats.decoded_lines += 1;
                self.frame(None, "-", None, &frame)
            }
            Err(frame_error) if looks_bare => {
                let message = format!("bare frame: {frame_error}");
                self.rejected_line(name, number, &message, frame_error.reason.as_str(), None)
            }
            Err(_) => self.rejected_line(name, number, &error.to_string(), error.reason.as_str(), None),
        }
    }
}

/// The [`Decoder`] as the line loop's sink: every line written or counted at once; the first error (with
/// `--strict`, or a failed write) stops the loop and is returned by [`Decoder::candump`].
struct DecoderLines<'d> {
    decoder: &'d mut Decoder,
    name: &'d str,
    error: Option<anyhow::Error>,
}

impl DecoderLines<'_> {
    #[inline(always)]
    fn flow(&mut self, result: Result<()>) -> ControlFlow<()> {
        match result {
            Ok(()) => ControlFlow::Continue(()),
            Err(error) => self.fail(error),
        }
    }

    #[cold]
    fn fail(&mut self, error: anyhow::Error) -> ControlFlow<()> {
        self.error = Some(error);
        ControlFlow::Break(())
    }
}

impl LineSink for DecoderLines<'_> {
    #[inline(always)]
    fn frame(&mut self, number: u64, line: FrameLine<'_>) -> ControlFlow<()> {
        let decoder = &mut *self.decoder;
        decoder.stats.decoded_lines += 1;
        match decoder.frame(line.ts, line.iface, line.dir, line.frame) {
            Ok(()) => ControlFlow::Continue(()),
            Err(error) => self.fail(in_line(error, self.name, number)),
        }
    }

    fn skipped(&mut self, number: u64, line: Line<'_>) -> ControlFlow<()> {
        let result = self.decoder.skipped_line(self.name, number, line);
        self.flow(result)
    }

    fn unparsed(&mut self, number: u64, text: &[u8], error: candump::LineError) -> ControlFlow<()> {
        let result = self.decoder.unparsed_line(self.name, number, text, error);
        self.flow(result)
    }

    #[inline(never)]
    fn too_long(&mut self, number: u64, length: usize) -> ControlFlow<()> {
        let message = candump::line_too_long(length);
        let reason = Reason::LineTooLong.as_str();
        let result = self.decoder.rejected_line(self.name, number, &message, reason, Some(length as u64));
        self.flow(result)
    }
}
