#!/usr/bin/env python3
"""What a link carried, by RTPS stream: reads a pcap of raw IPv4 packets (netem_relay
--capture-a-to-b, or any LINKTYPE_RAW / Ethernet capture) and prints, per time bin, the kbit/s
of each class:

  video      DATA_FRAG of the writer that sent the most fragmented data (the camera stream)
  resent     that writer's fragments seen before (repairs), counted apart
  data       other user DATA / DATA_FRAG (scans, odometry, health, lease, ...)
  builtin    discovery and DDS Security's builtin endpoints (entity kinds 0xc*)
  control    datagrams with no DATA: heartbeats, acknacks, gaps
  other      not RTPS (e.g. WireGuard, ICMP)

A datagram counts whole (IP bytes) in the class of its first DATA or DATA_FRAG submessage.
Only unencrypted RTPS can be read (the step bench runs without DDS Security); inside
WireGuard or with encrypted submessages everything is "other".

Usage: rtps_usage.py [--bin-s 1] [--origin EPOCH_S] [--from-s A] [--to-s B] PCAP"""
import argparse
import struct
import sys
from collections import defaultdict

CLASSES = ["video", "resent", "data", "builtin", "control", "other"]


def packets(path):
    """(epoch s, IP packet bytes (truncated), original length) of a pcap."""
    with open(path, "rb") as f:
        head = f.read(24)
        if len(head) < 24:
            sys.exit(f"rtps_usage: {path}: not a pcap")
        magic = struct.unpack("<I", head[:4])[0]
        if magic == 0xa1b2c3d4:
            endian = "<"
        elif magic == 0xd4c3b2a1:
            endian = ">"
        else:
            sys.exit(f"rtps_usage: {path}: not a microsecond pcap")
        linktype = struct.unpack(endian + "I", head[20:24])[0]
        skip = {101: 0, 1: 14, 113: 16}.get(linktype)
        if skip is None:
            sys.exit(f"rtps_usage: {path}: link type {linktype} not read")
        while True:
            rec = f.read(16)
            if len(rec) < 16:
                return
            sec, usec, incl, orig = struct.unpack(endian + "IIII", rec)
            data = f.read(incl)
            yield sec + usec / 1e6, data[skip:], orig - skip


def classify(ip, seen, video_writer):
    """Class name and, for data, the (writer key, bytes) to tally."""
    if len(ip) < 28 or ip[0] >> 4 != 4 or ip[9] != 17:
        return "other", None
    ihl = (ip[0] & 0x0F) * 4
    rtps = ip[ihl + 8:]
    if rtps[:4] != b"RTPS" or len(rtps) < 20:
        return "other", None
    prefix = rtps[8:20]
    at = 20
    while at + 4 <= len(rtps):
        kind, flags = rtps[at], rtps[at + 1]
        e = "<" if flags & 1 else ">"
        length = struct.unpack(e + "H", rtps[at + 2:at + 4])[0]
        body = rtps[at + 4:]
        if kind in (0x15, 0x16) and len(body) >= 20:  # DATA, DATA_FRAG
            writer = body[8:12]
            high, low = struct.unpack(e + "iI", body[12:20])
            sn = (high << 32) | low
            if writer[3] & 0xC0 == 0xC0:
                return "builtin", None
            if kind == 0x16 and len(body) >= 24:
                frag = struct.unpack(e + "I", body[20:24])[0]
                key = (prefix, writer)
                if video_writer is not None and key == video_writer:
                    return ("resent" if (sn, frag) in seen.setdefault(key, set()) else "video"), (
                        key, sn, frag)
                return "data", (key, sn, frag)
            return "data", None
        if length == 0:
            break
        at += 4 + length
    return "control", None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin-s", type=float, default=1.0)
    parser.add_argument("--origin", type=float, default=None, help="epoch s of time 0")
    parser.add_argument("--from-s", type=float, default=None)
    parser.add_argument("--to-s", type=float, default=None)
    parser.add_argument("pcap")
    args = parser.parse_args()
    records = list(packets(args.pcap))
    if not records:
        sys.exit("rtps_usage: no packets")
    # The video writer: the one that sent the most fragmented bytes.
    frag_bytes = defaultdict(int)
    for _, ip, length in records:
        _, tally = classify(ip, {}, None)
        if tally is not None:
            frag_bytes[tally[0]] += length
    video_writer = max(frag_bytes, key=frag_bytes.get) if frag_bytes else None
    origin = args.origin if args.origin is not None else records[0][0]
    start = args.from_s if args.from_s is not None else 0.0
    bins = defaultdict(lambda: defaultdict(int))
    totals = defaultdict(int)
    seen = {}
    for t, ip, length in records:
        cls, tally = classify(ip, seen, video_writer)
        if tally is not None and tally[0] == video_writer:
            seen.setdefault(tally[0], set()).add((tally[1], tally[2]))
        rel = t - origin
        if (args.from_s is not None and rel < args.from_s) or (args.to_s is not None and rel >= args.to_s):
            continue
        bins[int((rel - start) // args.bin_s)][cls] += length
        totals[cls] += length
    if not bins:
        sys.exit("rtps_usage: no packets in the interval")
    print("t_s," + ",".join(f"{c}_kbit_s" for c in CLASSES))
    for b in sorted(bins):
        row = bins[b]
        print(f"{start + b * args.bin_s:.1f}," +
              ",".join(f"{row[c] * 8 / 1e3 / args.bin_s:.0f}" for c in CLASSES))
    if args.from_s is not None and args.to_s is not None:
        span = args.to_s - args.from_s
    else:
        span = (max(bins) - min(bins) + 1) * args.bin_s
    total = sum(totals.values())
    print("total," + ",".join(f"{totals[c] * 8 / 1e3 / span:.0f}" for c in CLASSES))
    print("share," + ",".join(f"{totals[c] / total:.0%}" if total else "-" for c in CLASSES))


if __name__ == "__main__":
    main()
