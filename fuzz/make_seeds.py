#!/usr/bin/env python3
"""Writes the seed corpus fuzz/seeds/<target>/ (run from fuzz/seeds). The binary layouts are the ones the
checks in src/fuzzing.rs read; the files are committed, this only documents how they were made."""
import os, struct
def w(target, name, data):
    os.makedirs(target, exist_ok=True)
    if isinstance(data, str): data = data.encode()
    open(f"{target}/{name}", "wb").write(data)

lines = {
 "log_v2_status": "(1700000000.002500) can0 211#00000103000000B1",
 "log_rx": "(1600000000.000000)   can0 123#00 R",
 "log_nanos_tx": "(1700000000.123456789) vcan10 311#FFFFFFC100000012 T",
 "log_relative": "(000.123456) can0 251#0000000F00000054",
 "log_ext_remote": "(0.000000) can0 20000080# R",
 "log_remote_dlc": "(1700000000.000000) can0 123#R8_E",
 "log_raw_dlc": "(1700000000.000000) can0 123#1122334455667788_E",
 "log_dots": "(1700000000.000000) can0 5A1#11.2233.44556677.88",
 "log_fd": "(1700000000.000000) can0 123##5001122",
 "log_errorframe": "(1700000000.000000) can0 20000004#0008000000007800",
 "log_ext": "(1700000000.000000) can0 00000123#11",
 "log_xl": "(1700000000.000000) can0 45123#81:00:12345678#112233",
 "log_crlf": "(1700000000.010000) can0 111#012C000000000000\r",
 "buffer_two_lines": "(1700000000.002500) can0 211#00000103000000B1 R\r\n(1700000000.004500) can0 221#0011\n",
 "buffer_padded": "(1700000000.002500)" + " " * 40 + "can0 211#0011\n(1.0) can0 1#\n",
 "bare_no_stamp": "can0 421#01",
 "dropcount": "DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 7)",
 "comment": "# recorded on the bench",
 "console_stamped": " (1600000000.123456)  can0  151   [8]  00 01 02 03 04 05 06 07",
 "console_plain": "  can0  221   [8]  00 96 00 00 00 00 00 00",
 "console_dated": " (2020-12-19 12:04:45.485261)  can0  151   [8]  00 01 02 03 04 05 06 07",
 "console_fd_x": " (000.000250)  can0  RX B E  123  [12]  00 01 02 03 04 05 06 07 08 09 0A 0B",
 "console_color": " \x1b[1;31m(1600000000.123456) \x1b[1;31mcan0\x1b[0m  151   [8]  00 01 02 03 04 05 06 07\x1b[0m",
 "console_ascii": "  can0       151   [8]  41 42 43 44 45 46 47 48   'ABCDEFGH'",
 "console_remote": "  can0  151   [5]  remote request",
 "console_raw_dlc": "  can0  151   {9}  00 01 02 03 04 05 06 07",
 "console_errorframe": "  can0  20000004   [8]  00 08 00 00 00 00 78 00   ERRORFRAME",
 "console_error_text": "\tcontroller-problem{tx-error-warning}",
 "console_xl": "   xl0  123 [0003] (45|81:00:12345678) 11 22 33",
 "console_delta": " (000.020000)  can0  311   [8]  00 00 00 10 00 00 00 12",
 "empty": "",
}
for n, l in lines.items(): w("candump_line", n, l)

log = "\n".join([lines[k] for k in ["log_v2_status","console_plain","comment","dropcount","log_fd","console_errorframe","console_error_text"]]) + "\n"
# reader: capacity, max/4, n, sizes..., text
w("candump_reader", "mixed_small_buffer", bytes([3, 16, 3, 1, 5, 0]) + log.encode())
w("candump_reader", "long_line_limit", bytes([8, 2, 2, 7, 2]) + b"short\n" + b"x"*40 + b"\nok\n" + b"y"*9)
w("candump_reader", "crlf_no_final_newline", bytes([1, 255, 1, 64]) + b"a\r\n\r\n\nlast")
w("candump_reader", "empty_lines", bytes([2, 1, 0]) + b"\n\n\n")

def ser(t, c, payload, fid):
    b = bytes([0x5A,0xA5,0x0A,t,c]) + bytes(payload) + bytes([fid])
    return b + bytes([sum(b) & 0xFF])
manual = ser(0x55,1,[2,0,10,0,0,0],0)
status = ser(0xAA,1,[0,2,1,3,0,0x40],7)
motion = ser(0xAA,2,[0,0x96,0,0,0,0],3)
light = ser(0x55,2,[1,3,0x32,0,0,0],0)
motor = ser(0xAA,3,[0,0x10,0x01,0x2C,0x1E,0],1)
bad = bytearray(status); bad[12] ^= 0xFF
w("serial_stream", "frames_back_to_back", bytes([5]) + manual + status + motion + light + motor)
w("serial_stream", "noise_between", bytes([13]) + b"\x00\x5a\x5a" + status + b"\x5a\xa5\x0b\x01" + motion + b"\xff"*7 + manual[:6])
w("serial_stream", "bad_checksum_then_good", bytes([1]) + bytes(bad) + status)
w("serial_stream", "false_start", bytes([2]) + b"\x5a\xa5\x0a\xaa" + manual)

def v1sum(i, d):
    return ((i & 0xFF) + (i >> 8) + len(d) + sum(d[:-1])) & 0xFF
def cd(kind, idx, data):
    return bytes([kind, idx, len(data)]) + bytes(data)
w("can_decode", "v2_motion", cd(0, 0, [0,0x96,0,0x64,0,0,0,0]))
w("can_decode", "v2_light", cd(0, 1, [1,3,0x32,0,0,0,0,5]))
w("can_decode", "v2_status", cd(0, 2, [0,0,1,3,0,0,0,0xB1]))
w("can_decode", "v2_mode", cd(0, 13, [1]))
w("can_decode", "v2_fault_clear", cd(0, 14, [2]))
w("can_decode", "v2_version_request", cd(0, 11, [1]))
w("can_decode", "v2_odometry", cd(0, 10, [0xFF,0xFF,0xFF,0xC1,0,0,0,0x12]))
d = [1,0,10,0,0,0,4,0]; d[7] = v1sum(0x130, d)
w("can_decode", "v1_motion", cd(0, 16, d))
d = [0,1,1,3,0,0,9,0]; d[7] = v1sum(0x151, d)
w("can_decode", "v1_status_0x151", cd(0, 15, d))
w("can_decode", "short_motor", cd(0, 6, [0,0x10]))
w("can_decode", "extended_raw", bytes([0x0C]) + struct.pack(">I", 0x18EEFF01) + bytes([8]) + bytes(range(8)))
w("can_decode", "fd", bytes([0x07 | 0x20, 0, 9]) + bytes(range(12)))
w("can_decode", "error_frame", bytes([0x0E]) + struct.pack(">I", 4) + bytes([8, 0,8,0,0,0,0,0x78,0]))
w("can_decode", "remote", bytes([0x05, 3, 8]))

# summary: records of selector, stamp (nanos u32, then secs), frame
def stamp_abs(off, ns): return struct.pack(">I", ns) + struct.pack(">H", off)
def rec_can(sel, stamp, kind, idx, data): return bytes([sel]) + stamp + cd(kind, idx, data)
s = b""
for i in range(6):
    s += rec_can(0x02, stamp_abs(i, i*20_000_000), 0, 2, [0,1,1,3,0,0,0,i])
    s += rec_can(0x06, stamp_abs(i, i*20_000_000+5), 0, 3, [0,0x96,0,0,0,0,0,0])
    s += rec_can(0x02, stamp_abs(i, i*20_000_000+9), 0, 10, [0,0,0,i*10,0,0,0,i*10])
s += rec_can(0x02, stamp_abs(7, 0), 0, 2, [2,1,0,0xDC,0,1,0,9])  # E-stop, low battery, a fault bit
s += bytes([0x02]) + stamp_abs(8, 0)  # a record cut short
w("summary", "session_v2", s)
m = [1,0,10,0,0,0,4,0]; m[7] = v1sum(0x130, m)
w("summary", "no_stamps_v1", rec_can(0x00, b"", 0, 16, m) + rec_can(0x10, b"", 0, 15, [0]*8))
rel = lambda ns, secs: struct.pack(">I", ns) + struct.pack(">H", secs)
w("summary", "serial_relative", bytes([0x81]) + rel(1000, 1) + bytes([0,0,0,0,1,0,2,1,3,0,0x40,7]) + bytes([0x81]) + rel(2000, 1) + bytes([0,0,0,0,2,0,0x96,0,0,0,0,3]))
w("summary", "error_and_extended", bytes([0x02]) + stamp_abs(1, 0) + bytes([0x0E]) + struct.pack(">I", 4) + bytes([8,0,8,0,0,0,0,0x78,0]) + bytes([0x02]) + stamp_abs(1, 1) + bytes([0x0C]) + struct.pack(">I", 0x18EEFF01) + bytes([3,1,2,3]))

for n, (f, t) in {
  "can_motion": (0, "111#0096000000000000"),
  "can_zero_motion": (0, "111#0000000000000000"),
  "can_mode": (0, "421#01"),
  "can_lights": (0, "121#01031E0000000000"),
  "can_v1_motion": (0, "130#01000A0000000044"),
  "can_remote": (0, "111#R"),
  "can_extended": (0, "00000111#0096"),
  "can_bad_column": (0, "123#1122334455667788zz"),
  "serial_motion": (1, "5A A5 0A 55 01 02 00 0A 00 00 00 00 6B"),
  "serial_fix_checksum": (3, "5A:A5:0A:55:02:01:03:32:00:00:00:00"),
  "serial_bad": (1, "5A A5 0B 55 01 02 00 0A 00 00 00 00"),
}.items():
    w("send_raw_plan", n, bytes([f]) + t.encode())
