#!/usr/bin/env python3
"""Lists what an RTPS capture carries, from tshark's dissection (PDML on stdin), one line each:

  endpoint|TOPIC|TYPE|ENTITY_KIND|PARTITIONS   an endpoint announced in discovery (SEDP)
  sample|TOPIC|ENCAPSULATION                   a user DATA submessage (its topic as the dissector
                                               learned it from discovery)

ENTITY_KIND is the endpoint GUID's last byte (0x03 writer without key, 0x02 with key, 0x04 reader
without key, 0x07 with key); PARTITIONS comma-separated, empty for the default partition.
"""
import sys
import xml.etree.ElementTree as ET

DATA = {"0x15", "0x16"}  # DATA, DATA_FRAG


def first(node, name):
    for f in node.iter("field"):
        if f.get("name") == name:
            return f.get("show", "")
    return None


def main():
    for _, elem in ET.iterparse(sys.stdin.buffer, events=("end",)):
        if elem.tag != "packet":
            continue
        for sm in elem.iter("field"):
            if sm.get("name") != "rtps.sm.id" or sm.get("show") not in DATA:
                continue
            topic = first(sm, "rtps.param.topicName")
            guid = first(sm, "rtps.param.endpoint_guid")
            if guid is not None and topic is not None:
                parts = [f.get("show", "") for f in sm.iter("field")
                         if f.get("name") == "rtps.param.partition"]
                kind = "0x" + guid.split(":")[-1]
                print(f"endpoint|{topic}|{first(sm, 'rtps.param.typeName') or ''}|{kind}|{','.join(parts)}")
            elif topic is not None:
                encap = first(sm, "rtps.param.serialize.encap_kind")
                if encap is not None:
                    print(f"sample|{topic}|{encap}")
        elem.clear()


if __name__ == "__main__":
    main()
