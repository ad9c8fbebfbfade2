use std::io::{self, Read, Write};

use super::*;

const LOG: &[u8] = b"(1700000000.000000) can0 211#00000103000000B1\n(1700000000.020000) can0 421#01\n";

fn open(bytes: &[u8], name: &str) -> Result<(Vec<u8>, LogFormat), FormatError> {
    let (mut reader, format) = open_log(io::Cursor::new(bytes.to_vec()), name)?;
    let mut text = Vec::new();
    reader.read_to_end(&mut text).map_err(|source| FormatError::Io { name: name.into(), source })?;
    Ok((text, format))
}

/// `data` compressed as the command-line tools write it (zstd with its checksum), for open and inflate.
pub(in crate::candump) fn compress(compression: Compression, data: &[u8]) -> Vec<u8> {
    match compression {
        Compression::Gzip => {
            let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        Compression::Zstd => {
            let mut encoder = zstd::stream::write::Encoder::new(Vec::new(), 3).unwrap();
            encoder.include_checksum(true).unwrap();
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        Compression::Xz => {
            let mut encoder = liblzma::write::XzEncoder::new(Vec::new(), 6);
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        Compression::Bzip2 => {
            let mut encoder = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::default());
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
    }
}

pub(in crate::candump) const ALL: [Compression; 4] =
    [Compression::Gzip, Compression::Zstd, Compression::Xz, Compression::Bzip2];

#[test]
fn compressed_logs_are_recognised_by_their_bytes_and_decompressed() {
    for compression in ALL {
        // The name says nothing: the magic bytes decide.
        let (text, format) = open(&compress(compression, LOG), "capture.log").unwrap();
        assert_eq!(text, LOG, "{compression:?}");
        assert_eq!(format, LogFormat { text: TextFormat::Candump, compression: Some(compression) });
    }
}

#[test]
fn concatenated_gzip_members_are_all_read() {
    let mut two = compress(Compression::Gzip, &LOG[..46]);
    two.extend(compress(Compression::Gzip, &LOG[46..]));
    assert_eq!(open(&two, "x.gz").unwrap().0, LOG);
}

#[test]
fn a_truncated_compressed_log_is_an_error_naming_the_compression() {
    let big: Vec<u8> = LOG.iter().copied().cycle().take(200_000).collect();
    for compression in ALL {
        let whole = compress(compression, &big);
        let cut = &whole[..whole.len() / 2];
        let error = open(cut, "cut.log").unwrap_err().to_string();
        assert!(error.starts_with("cannot read cut.log: "), "{error}");
        assert!(error.contains(&format!("truncated {} data", compression.name())), "{error}");
    }
}

#[test]
fn a_compressed_asc_log_is_read_as_asc() {
    let asc = b"date Tue Nov 24 10:00:00.000 2026\nbase hex  timestamps absolute\n   0.02 1 211 Rx d 1 00\n";
    let (_, format) = open(&compress(Compression::Gzip, asc), "x.asc.gz").unwrap();
    assert_eq!(format, LogFormat { text: TextFormat::VectorAsc, compression: Some(Compression::Gzip) });
}

#[test]
fn a_utf8_bom_is_skipped_at_the_start_only() {
    let mut with_bom = UTF8_BOM.to_vec();
    with_bom.extend_from_slice(LOG);
    assert_eq!(open(&with_bom, "x").unwrap().0, LOG);
    let (text, _) = open(&compress(Compression::Zstd, &with_bom), "x").unwrap();
    assert_eq!(text, LOG);
    // A BOM later in the file is data, left to the line parser to reject.
    let mut later = LOG.to_vec();
    later.extend_from_slice(UTF8_BOM);
    assert_eq!(open(&later, "x").unwrap().0, later);
}

#[test]
fn text_formats_are_recognised_from_the_first_lines() {
    let cases: &[(&[u8], TextFormat)] = &[
        (b"date Tue Nov 24 10:00:00.000 2026\r\nbase hex  timestamps absolute\r\n", TextFormat::VectorAsc),
        (b";$FILEVERSION=1.1\n;$STARTTIME=46350.4\n", TextFormat::PeakTrc { version: 11 }),
        (b";$FILEVERSION=1.3\n", TextFormat::PeakTrc { version: 13 }),
        (b";$FILEVERSION=2.0\n", TextFormat::PeakTrc { version: 20 }),
        (b";$FILEVERSION=2.1\n", TextFormat::PeakTrc { version: 21 }),
        (
            b";####\n;   x.trc\n;    Start time: 24.11.2026 10:00:00.000\n;\n     1)  20  0211  1  00\n",
            TextFormat::PeakTrc { version: 10 },
        ),
        // candump in every shape, with comments first: never refused.
        (LOG, TextFormat::Candump),
        (b"  can0  211   [8]  00 00 01 03 00 00 00 B1\n", TextFormat::Candump),
        (b"# comment\n; another\n(1.0) can0 211#00\n", TextFormat::Candump),
        (b";\n;\n(1.0) can0 211#00\n", TextFormat::Candump),
        (b"// notes\n(1.0) can0 211#00\n", TextFormat::Candump),
        (b"date\n(1.0) can0 211#00\n", TextFormat::Candump),
        (b"<0x18eeff01> [8] 05 a0 be 1c 00 a0 a0 c0 \n", TextFormat::Candump),
        (b"211#00000103000000B1\n", TextFormat::Candump),
        (b"BZh91AY\n", TextFormat::Candump),
        (b"", TextFormat::Candump),
        (b"\n\n", TextFormat::Candump),
    ];
    for (text, expected) in cases {
        let (_, format) =
            open(text, "x").unwrap_or_else(|e| panic!("{}: {e}", String::from_utf8_lossy(text)));
        assert_eq!(format.text, *expected, "{}", String::from_utf8_lossy(text));
        assert_eq!(format.compression, None);
    }
}

#[test]
fn unsupported_formats_are_refused_in_one_line_with_a_converter() {
    let cases: &[(&[u8], &str, &str)] = &[
        (b"LOGG\x90\x00\x00\x00", "a Vector BLF log", "python -m can.logconvert f.x f.log"),
        (b"\xd4\xc3\xb2\xa1\x02\x00\x04\x00", "a pcap capture", "Wireshark"),
        (b"\x0a\x0d\x0d\x0a\x1c\x00\x00\x00", "a pcapng capture", "Wireshark"),
        (b"MDF     4.10    ", "an ASAM MDF (MF4) log", "python -m can.logconvert"),
        (b"\xff\xfe(\x001\x00", "UTF-16 text", "iconv -f UTF-16 -t UTF-8 f.x"),
        (
            b"Time Stamp,ID,Extended,Bus,LEN,D1\n1,00000211,false,0,1,00,\n",
            "a SavvyCAN/GVRET CSV log",
            "SavvyCAN",
        ),
        (b"ID,Data Bytes\n00000211,00 \n", "a SavvyCAN/GVRET CSV log", "SavvyCAN"),
        (b"1.000000 CXX GVRET-PC\n", "a CRTD log", "SavvyCAN"),
        (b"1.000000 R11 00000211 00 01\n", "a CRTD log", "SavvyCAN"),
        (b"***BUSMASTER Ver 3.2.2***\n", "a BUSMASTER log", "SavvyCAN"),
        (
            b"//------\nMicrochip Technology Inc.\nCAN BUS Analyzer\n",
            "a Microchip CAN BUS Analyzer log",
            "SavvyCAN",
        ),
        (b"@ TEXT @ 1 @ 8 @ 0\n", "a CarBusAnalyzer trace", "SavvyCAN"),
        (b"10:00:00.020 R 18FF0001 01 02\r\n", "a Yacht Devices RAW log", "candump -L"),
        (
            b"2026-11-24-10:00:00.020,3,130823,27,255,8,00,df,13,99,ff,00,0f,01\n",
            "an Actisense/canboat CSV log",
            "candump -L",
        ),
        (
            b"(0.001) 18F0090B    06 F009 0B --> FF [0008] FFFFFFFFFFFFFFFF\n",
            "a TruckDevil dump",
            "candump -L",
        ),
        (b"timestamp,arbitration_id,extended,remote,error,dlc,data\n", "a python-can CSV log", "logconvert"),
        (b";$FILEVERSION=3.0\n", "a PEAK trc log of a version not read", "logconvert"),
    ];
    for (bytes, format, advice) in cases {
        let error = open(bytes, "f.x").unwrap_err();
        assert_eq!(error.unsupported_format(), Some(*format));
        let message = error.to_string();
        assert!(
            message.starts_with(&format!("f.x is {format}, which tracerctl does not read: ")),
            "{message}"
        );
        assert!(message.contains(advice), "{message}");
        assert!(!message.contains('\n'));
        let failure = crate::exit::Failure::from(error);
        assert_eq!(failure.code, crate::exit::DATA_ERROR);
    }
    // Compressed, a refused format is refused all the same.
    let error = open(&compress(Compression::Xz, b"LOGG\x90\x00"), "f.blf.xz").unwrap_err();
    assert_eq!(error.unsupported_format(), Some("a Vector BLF log"));
}

/// A live pipe: one line now, then nothing for a long time. Reading more would hang the user.
struct OneLineThenBlock(Option<&'static [u8]>);

impl Read for OneLineThenBlock {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let Some(line) = self.0.take() else { panic!("read past the first line while sniffing") };
        buf[..line.len()].copy_from_slice(line);
        Ok(line.len())
    }
}

#[test]
fn a_live_candump_stream_is_decided_by_its_first_line() {
    for line in [&b"(1700000000.000000) can0 211#00000103000000B1\n"[..], b"  can0  211   [1]  00\n"] {
        let (_, format) = open_log(OneLineThenBlock(Some(line)), "<stdin>").unwrap();
        assert_eq!(format.text, TextFormat::Candump);
    }
}

#[test]
fn a_corrupt_compressed_header_is_a_read_error_naming_the_compression() {
    let error = open(b"\x1f\x8b\x08\xff\xff\xff\xff\xff\xff\xff\xff\xff", "bad.gz").unwrap_err();
    assert!(error.unsupported_format().is_none());
    let message = error.to_string();
    assert!(message.starts_with("cannot read bad.gz: ") && message.contains("gzip"), "{message}");
    assert_eq!(crate::exit::Failure::from(error).code, crate::exit::FAILURE);
}

/// Raw bytes (an RS232 capture, random data) are refused in one line that points at `--serial`; text with a
/// stray control byte, coloured console output and a compressed log are still text.
#[test]
fn binary_data_is_refused_as_not_a_text_log() {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let random: Vec<u8> = (0..3000)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 32) as u8
        })
        .collect();
    // Two RS232 frames: 5A A5, length, type, command, payload, id, checksum.
    let serial: &[u8] = b"\x5A\xA5\x0A\xAA\x01\x00\x00\x01\x03\x00\x00\x00\xB1\x5A\xA5\x0A\xAA\x02\x00\x00\x00\x00\x00\x00\x01\x0C";
    for (bytes, name) in [(random.as_slice(), "random.bin"), (serial, "port.bin")] {
        let error = open(bytes, name).unwrap_err();
        assert_eq!(
            error.to_string(),
            format!(
                "{name} is binary data, not a text log, which tracerctl does not read: an RS232 capture? use \
                 `tracerctl decode --serial {name}`"
            )
        );
        assert_eq!(crate::exit::Failure::from(error).code, crate::exit::DATA_ERROR);
        assert!(open(&compress(Compression::Gzip, bytes), name).is_err(), "{name} compressed");
    }
    let mut stray = LOG.to_vec();
    stray[60] = 0;
    let colour = b"\x1b[1;31m  can0  211   [8]  00 00 01 03 00 00 00 B1\x1b[0m\n";
    for text in [&stray[..], colour, LOG] {
        assert_eq!(open(text, "x.log").unwrap().1.text, TextFormat::Candump, "{text:?}");
    }
}
